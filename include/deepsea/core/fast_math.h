#pragma once
/// \file log2, exp2, pow, exp and acos in float for vectorised rows (the camera stage's, the
/// runtime's lamp and direct rows): plain arithmetic on a float's bits, so that GCC vectorises
/// them inline (glibc's vector log, exp, acos and pow, called once per value, cost the camera
/// stage more than all its other arithmetic). In double, for the tests' references, the
/// standard functions. `ExactMath` and `FastMath` hand them to optics' equations, which take
/// the functions as a template argument (`transmission`, `gaussian_lamp_term`, `lamp_angle`).

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
/// e^y for |y| <= ln 2 / 2 by its Taylor series to degree 7 (truncation below 5e-9): the part
/// of fast_exp2 and fast_exp between their powers of two.
[[gnu::always_inline]] inline float exp_taylor7(float y) {
    return 1.0f +
           y * (1.0f + y * (0.5f + y * (1.0f / 6.0f +
                                        y * (1.0f / 24.0f +
                                             y * (1.0f / 120.0f +
                                                  y * (1.0f / 720.0f + y * (1.0f / 5040.0f)))))));
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
        const float p = exp_taylor7(y);
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

/// e^x for x <= 88 (the exponents of attenuation and lamp profiles are <= 0): x = n ln 2 + r,
/// n = round(x / ln 2), r by ln 2 in two parts (Cody and Waite), |r| <= ln 2 / 2; e^r by its
/// Taylor series to degree 7 (truncation below 5e-9); 2^n added to the exponent's bits. x is
/// clamped to -125 ln 2 first, so that results below 2^-125 (2.4e-38) are 2^-125, not garbage.
/// Relative error a few float roundings above that (tests: below 1e-6 over [-87, 0]). The
/// integer step keeps fast-math from reassociating the result with its factors, so that two
/// loops that multiply it alike give the same bits. In double: std::exp.
template <class F>
[[gnu::always_inline]] inline F fast_exp(F x) {
    if constexpr (std::is_same_v<F, float>) {
        using namespace fast_math_detail;
        x = x > -86.64339f ? x : -86.64339f;  // -125 ln 2: n >= -125
        const float n = std::floor(x * 1.4426950408889634f + 0.5f);
        const float r = (x - n * 0.693145751953125f) - n * 1.428606765330187e-06f;
        const float p = exp_taylor7(r);
        // n * 2^23, not n << 23: a left shift of a negative n is undefined (UBSan); the same code.
        return float_of(bits_of(p) + std::int32_t(n) * (std::int32_t(1) << 23));
    } else {
        return std::exp(x);
    }
}

/// acos(x) for x in [-1, 1] (radians): Abramowitz and Stegun 4.4.46, acos|x| = sqrt(1 - |x|)
/// times a polynomial of degree 7 in |x| (its error below 2e-8), pi minus it for x < 0.
/// Absolute error below 1e-6 in float (tests). In double: std::acos.
template <class F>
[[gnu::always_inline]] inline F fast_acos(F x) {
    if constexpr (std::is_same_v<F, float>) {
        const float a = std::fabs(x);
        const float p =
            1.5707963050f +
            a * (-0.2145988016f +
                 a * (0.0889789874f +
                      a * (-0.0501743046f +
                           a * (0.0308918810f +
                                a * (-0.0170881256f + a * (0.0066700901f - a * 0.0012624911f))))));
        const float r = std::sqrt(1.0f - a) * p;
        return x < 0.0f ? 3.14159265358979f - r : r;
    } else {
        return std::acos(x);
    }
}

/// The standard functions, for optics' equations (`Math` template argument): what the
/// reference and the tests evaluate.
struct ExactMath {
    template <class T>
    static T exp(T x) {
        using std::exp;
        return exp(x);
    }
    template <class T>
    static T acos(T x) {
        using std::acos;
        return acos(x);
    }
};

/// fast_exp and fast_acos, for optics' equations in the runtime's float rows (inline, within
/// a few float roundings: see each).
struct FastMath {
    template <class T>
    [[gnu::always_inline]] static T exp(T x) {
        return fast_exp(x);
    }
    template <class T>
    [[gnu::always_inline]] static T acos(T x) {
        return fast_acos(x);
    }
};

}  // namespace deepsea
