// The sensor kernel's Gaussian path (rows.cpp's noisy_values) written with AVX2 and FMA
// intrinsics, 8 values at a time, for the common case: sensor noise, no Bayer mosaic. The same
// operations in the same order as the x86-64-v3 clone GCC makes of noisy_values under
// -ffast-math (a reciprocal square root with one Newton step, the skewness term associated as
// there), so that the bits are those of that clone; written by hand so that it reads the
// radiance where it lies (unaligned: no copy into the scratch), lists the exact path's values
// from a mask and, where asked, makes the image through the frame's table in the same loop
// (docs/camera-speed.md). A chunk's last values (fewer than 8) are computed as a masked vector
// of 8, so that every value of a row takes the same arithmetic.

#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "rows.h"

namespace deepsea::camera_rows {

#if defined(__x86_64__) && defined(__GNUC__)

namespace {

/// The chunk's arrays, as locals: the stores through them cannot change them.
struct Arrays {
    const float* __restrict radiance;
    const float* __restrict response;
    const float* __restrict dsnu;
    const float* __restrict normal;
    float* __restrict mean;
    float* __restrict raw;
    float* __restrict linear;
    const std::int32_t* __restrict chan;  // chunk_channels()
    const float* __restrict lut;
    float* __restrict shown;
    const std::uint8_t* __restrict code_lut;
    std::uint8_t* __restrict codes;
};

/// What the loop makes of the DN besides: nothing, display values or 8-bit codes.
enum class Show { None, Display, Codes };

/// The frame's parameters, broadcast once per chunk (locals: the loop's stores cannot change
/// them, so they stay in registers).
struct Params {
    __m256 t, dark, read_var, fw, K, black, black_half, max_dn, poisson_below;
};

__attribute__((target("avx2,fma"))) inline Params broadcast(const SensorParams& p) {
    return {_mm256_set1_ps(p.exposure_time_ms),
            _mm256_set1_ps(p.dark_electrons),
            _mm256_set1_ps(p.read_noise * p.read_noise),
            _mm256_set1_ps(p.full_well),
            _mm256_set1_ps(p.gain),
            _mm256_set1_ps(p.black),
            _mm256_set1_ps(p.black + 0.5f),  // dn + 0.5 folded into the fma, as GCC's
            _mm256_set1_ps(p.max_dn),
            _mm256_set1_ps(p.poisson_below)};
}

/// 8 floats from q, or the `mask`ed ones (kMasked).
template <bool kMasked>
__attribute__((target("avx2,fma"), always_inline)) inline __m256 load(const float* q,
                                                                      __m256i mask) {
    if constexpr (kMasked) return _mm256_maskload_ps(q, mask);
    return _mm256_loadu_ps(q);
}

template <bool kMasked>
__attribute__((target("avx2,fma"), always_inline)) inline void store(float* q, __m256i mask,
                                                                     __m256 x) {
    if constexpr (kMasked)
        _mm256_maskstore_ps(q, mask, x);
    else
        _mm256_storeu_ps(q, x);
}

/// 8 values from i on (kMasked: the `mask`ed ones, for a chunk's last values); returns the
/// exact path's flags as the low 8 bits. kLinear: also store the linear DN (the clone of
/// noisy_values<true, false>, whose skewness term GCC associates differently from
/// noisy_values<false, false>'s). kPoisson: flag means below SensorParams::poisson_below (where
/// it is 0, as for a read noise of 2 e- or more, no mean lies below it: the test would flag
/// nothing). kRaw: store every value's raw DN (else exact_values writes the exact path's alone).
template <bool kLinear, Show kShow, bool kPoisson, bool kRaw, bool kMasked>
__attribute__((target("avx2,fma"), always_inline)) inline int eight(const Params& p,
                                                                    const Arrays& a, int i,
                                                                    __m256i mask, int left) {
    const __m256 zero = _mm256_setzero_ps();
    const __m256 rt = _mm256_mul_ps(load<kMasked>(a.response + i, mask), p.t);
    const __m256 mean =
        _mm256_fmadd_ps(_mm256_max_ps(zero, load<kMasked>(a.radiance + i, mask)), rt, p.dark);
    const __m256 variance = _mm256_add_ps(mean, p.read_var);
    const __m256 r0 = _mm256_rsqrt_ps(variance);
    const __m256 r =
        _mm256_mul_ps(_mm256_fmadd_ps(_mm256_mul_ps(r0, variance), r0, _mm256_set1_ps(-3.0f)),
                      _mm256_mul_ps(r0, _mm256_set1_ps(-0.5f)));
    const __m256 z = load<kMasked>(a.normal + i, mask);
    const __m256 zz1 = _mm256_fmadd_ps(z, z, _mm256_set1_ps(-1.0f));
    const __m256 sigma = _mm256_mul_ps(variance, r);
    const __m256 sz = _mm256_mul_ps(sigma, z);
    const __m256 clip = _mm256_cmp_ps(p.fw, _mm256_fmadd_ps(sigma, _mm256_set1_ps(5.5f), mean),
                                      _CMP_LE_OS);  // 5.5: kClipReach
    const __m256 sixth = _mm256_set1_ps(1.0f / 6.0f);
    __m256 noise;
    if constexpr (kLinear) {
        const __m256 s = _mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(zz1, sixth), mean), r);
        noise = _mm256_fmadd_ps(s, r, sz);
    } else {
        const __m256 s = _mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(r, r), sixth), zz1);
        noise = _mm256_fmadd_ps(s, mean, sz);
    }
    const __m256 e = _mm256_add_ps(_mm256_add_ps(mean, load<kMasked>(a.dsnu + i, mask)), noise);
    __m256 dn;
    if constexpr (kLinear) {
        const __m256 linear = _mm256_fmadd_ps(e, p.K, p.black);
        store<kMasked>(a.linear + i, mask, linear);
        dn = _mm256_add_ps(linear, _mm256_set1_ps(0.5f));
    } else {
        dn = _mm256_fmadd_ps(e, p.K, p.black_half);  // + 0.5 folded, as GCC's
    }
    dn = _mm256_min_ps(_mm256_max_ps(_mm256_floor_ps(dn), zero), p.max_dn);
    if constexpr (kRaw) store<kMasked>(a.raw + i, mask, dn);
    if constexpr (kShow != Show::None) {  // the table's entry 3 dn + c (lookup_row)
        const __m256i d = _mm256_cvttps_epi32(dn);
        const __m256i at =
            _mm256_add_epi32(_mm256_add_epi32(d, _mm256_slli_epi32(d, 1)),
                             _mm256_load_si256(reinterpret_cast<const __m256i*>(a.chan + i)));
        if constexpr (kShow == Show::Display) {
            if constexpr (kMasked)
                store<true>(
                    a.shown + i, mask,
                    _mm256_mask_i32gather_ps(zero, a.lut, at, _mm256_castsi256_ps(mask), 4));
            else
                _mm256_storeu_ps(a.shown + i, _mm256_i32gather_ps(a.lut, at, 4));
        } else {
            read_codes(a.code_lut, at, a.codes + i, kMasked ? left : 8);
        }
    }
    __m256 exact = clip;
    if constexpr (kPoisson)
        exact = _mm256_or_ps(exact, _mm256_cmp_ps(mean, p.poisson_below, _CMP_LT_OS));
    const int flags = _mm256_movemask_ps(exact);
    if (flags) store<kMasked>(a.mean + i, mask, mean);  // the exact path reads these only
    return flags;
}

/// Appends the values i + k of the set bits k to the exact path's index list.
inline void append(int bits, int i, std::int32_t* index, int& m) {
    while (bits) {
        index[m++] = i + __builtin_ctz(unsigned(bits));
        bits &= bits - 1;
    }
}

template <bool kLinear, Show kShow, bool kPoisson, bool kRaw>
__attribute__((target("avx2,fma"))) int gaussian_values(const SensorParams& p, int n,
                                                        const RowBuffers& b) {
    const Params q = broadcast(p);
    const Arrays a{b.radiance, b.response,       b.dsnu, b.normal, b.mean,     b.raw,
                   b.linear,   chunk_channels(), b.lut,  b.shown,  b.code_lut, b.codes};
    std::int32_t* index = b.index;
    int m = 0, i = 0;
    for (; i + 8 <= n; i += 8)
        if (const int bits = eight<kLinear, kShow, kPoisson, kRaw, false>(q, a, i, __m256i(), 8))
            append(bits, i, index, m);
    if (i < n) {
        const __m256i mask =
            _mm256_cmpgt_epi32(_mm256_set1_epi32(n - i), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
        append(eight<kLinear, kShow, kPoisson, kRaw, true>(q, a, i, mask, n - i) &
                   ((1 << (n - i)) - 1),
               i, index, m);
    }
    return m;
}

template <Show kShow, bool kPoisson, bool kRaw>
int with_linear(const SensorParams& p, int n, const RowBuffers& b) {
    return p.keep_linear ? gaussian_values<true, kShow, kPoisson, kRaw>(p, n, b)
                         : gaussian_values<false, kShow, kPoisson, kRaw>(p, n, b);
}

template <Show kShow, bool kRaw>
int with_poisson(const SensorParams& p, int n, const RowBuffers& b) {
    return p.poisson_below > 0.0f ? with_linear<kShow, true, kRaw>(p, n, b)
                                  : with_linear<kShow, false, kRaw>(p, n, b);
}

/// The loop for the image it makes in the loop, every raw DN stored unless !p.keep_raw.
template <Show kShow>
int with_show(const SensorParams& p, int n, const RowBuffers& b) {
    return p.keep_raw ? with_poisson<kShow, true>(p, n, b) : with_poisson<kShow, false>(p, n, b);
}

}  // namespace

const bool kSensorAvx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");

int gaussian_values_avx2(const SensorParams& p, int n, const RowBuffers& b) {
    if (b.shown) return with_show<Show::Display>(p, n, b);
    if (b.codes) return with_show<Show::Codes>(p, n, b);
    return with_poisson<Show::None, true>(p, n, b);  // the image is made from the raw DN
}

#else

const bool kSensorAvx2 = false;

int gaussian_values_avx2(const SensorParams&, int, const RowBuffers&) { return 0; }

#endif

}  // namespace deepsea::camera_rows
