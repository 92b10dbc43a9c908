#pragma once
/// \file log2, exp2 and pow in float for the stage's vectorised rows: plain arithmetic on a
/// float's bits, so that GCC vectorises them inline (glibc's vector log, exp and pow, called
/// once per value, cost the stage more than all its other arithmetic). In double, for the
/// tests' references, the standard functions.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace deepsea {

namespace fast_math_detail {
[[gnu::always_inline]] inline std::int32_t bits_of(float x) {
    std::int32_t i;
    std::memcpy(&i, &x, sizeof i);
    return i;
}
[[gnu::always_inline]] inline float float_of(std::int32_t i) {
    float x;
    std::memcpy(&x, &i, sizeof x);
    return x;
}
}  // namespace fast_math_detail

/// log2(x) for a normal float x > 0: x = m 2^e with m in [sqrt(1/2), sqrt(2)), and
/// log2(m) = (2 / ln 2) atanh(s), s = (m - 1) / (m + 1), |s| <= 0.172, by its series to s^9
/// (truncation below 1e-9). Absolute error within a few float roundings of the result
/// (1e-6 at |log2 x| = 20, 1e-7 near 0). In double: std::log2.
template <class F>
[[gnu::always_inline]] inline F fast_log2(F x) {
    if constexpr (std::is_same_v<F, float>) {
        using namespace fast_math_detail;
        const std::int32_t b = bits_of(x);
        const std::int32_t shift = (b - 0x3f3504f3) & std::int32_t(0xff800000u);  // sqrt(1/2)
        const float m = float_of(b - shift), e = float(shift >> 23);
        const float s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
        return e + s * (2.8853900817779268f +
                        s2 * (0.9617966939259756f +
                              s2 * (0.5770780163555854f +
                                    s2 * (0.4121985831111324f + s2 * 0.3205988979753252f))));
    } else {
        return std::log2(x);
    }
}

/// 2^t for t in [-126, 127]: 2^round(t) from the bits, 2^f for f in [-1/2, 1/2] by its Taylor
/// series to degree 7 (truncation below 5e-9). Relative error a few float roundings. In
/// double: std::exp2.
template <class F>
[[gnu::always_inline]] inline F fast_exp2(F t) {
    if constexpr (std::is_same_v<F, float>) {
        using namespace fast_math_detail;
        const float n = std::floor(t + 0.5f), y = (t - n) * 0.6931471805599453f;
        const float p =
            1.0f +
            y * (1.0f + y * (0.5f + y * (1.0f / 6.0f +
                                         y * (1.0f / 24.0f +
                                              y * (1.0f / 120.0f +
                                                   y * (1.0f / 720.0f + y * (1.0f / 5040.0f)))))));
        return p * float_of((std::int32_t(n) + 127) << 23);
    } else {
        return std::exp2(t);
    }
}

/// Natural log: ln 2 log2(x).
template <class F>
[[gnu::always_inline]] inline F fast_log(F x) {
    return F(0.6931471805599453) * fast_log2(x);
}

/// x^e for x in [0, 1] and e > 0 (0 at 0; results below 2^-126 are 0); relative error below
/// 2e-6 (the log's rounding times e).
template <class F>
[[gnu::always_inline]] inline F fast_pow(F x, F e) {
    const F floor_ = F(1.1754943508222875e-38);  // the smallest normal float
    const F t = e * fast_log2(x > floor_ ? x : floor_);
    return x > F(0) && t > F(-126) ? fast_exp2(t) : F(0);
}

}  // namespace deepsea
