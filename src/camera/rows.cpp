// The camera stage's row kernels. Compiled with -ffast-math -fopenmp-simd (src/camera/
// CMakeLists.txt): GCC vectorises the loops marked `omp simd`, calling glibc's vector math
// (libmvec) for log, exp and sqrt, with an AVX2 clone picked at load time.

#include "rows.h"

#include <cmath>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "deepsea/camera/processing.h"
#include "deepsea/camera/sensor.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(DEEPSEA_NO_CLONES)
#define DEEPSEA_CAMERA_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define DEEPSEA_CAMERA_CLONES
#endif

namespace deepsea::camera_rows {

namespace {

/// i % 3 for the values of a chunk (chunks start at whole pixels).
struct Channels {
    alignas(64) std::int32_t c[kChunk];
    Channels() {
        for (int i = 0; i < kChunk; ++i) c[i] = i % 3;
    }
};
const Channels kChannels;

}  // namespace

const std::int32_t* chunk_channels() { return kChannels.c; }

namespace {

// Values, not std::max/min's references: a reference to a temporary inside an `omp simd` loop
// becomes a per-lane array that stops GCC from vectorising the loop.
inline float max_of(float a, float b) { return a > b ? a : b; }
inline float min_of(float a, float b) { return a < b ? a : b; }

/// Below a Gaussian shot noise's reach of the full well: where clipping can happen, the shot
/// and read noise are drawn apart (the read noise adds after the full well clips).
constexpr float kClipReach = 5.5f;  // > the largest normal deviate, 5.42

/// 1/k for the Poisson sums.
struct Reciprocals {
    float r[129];
    Reciprocals() {
        for (int k = 1; k <= 128; ++k) r[k] = 1.0f / float(k);
    }
};
const Reciprocals kInv;

/// The exact path's numbers for m gathered values: the read noise's normal, the Poisson's
/// uniform (from the shot stream's bits), the Gaussian shot electrons.
DEEPSEA_CAMERA_CLONES
void gather_exact(const SensorParams& p, std::uint32_t base, int m, const RowBuffers& b) {
    const std::int32_t* __restrict index = b.index;
    const float* __restrict mean = b.mean;
    const float* __restrict offset = b.dsnu;
    const float* __restrict normal = b.normal;
    float* __restrict cm = b.exact_mean;
    float* __restrict cu = b.exact_uniform;
    float* __restrict ce = b.exact_electrons;
    float* __restrict co = b.exact_offset;
    const NoiseKey shot_key = p.shot_key, read_key = p.read_key;
    const float read_noise = p.read_noise, poisson_below = p.poisson_below;
#pragma omp simd
    for (int j = 0; j < m; ++j) {
        const std::int32_t i = index[j];
        const std::uint32_t c = base + std::uint32_t(i);
        const float mu = mean[i];
        const std::uint32_t shot = noise_bits(shot_key, c);
        const float z_shot = normal[i];  // the deviate the Gaussian path used
        const float z_read = normal_from_bits<float>(noise_bits(read_key, c));
        const bool poisson = mu < poisson_below;
        cm[j] = poisson ? mu : 0.0f;
        cu[j] = poisson ? (float(std::int32_t(shot >> 8)) + 0.5f) * (1.0f / 16777216.0f) : 0.0f;
        const float gaussian = mu + std::sqrt(mu) * z_shot + (z_shot * z_shot - 1.0f) / 6.0f;
        ce[j] = gaussian > 0.0f ? gaussian : 0.0f;
        co[j] = offset[i] + read_noise * z_read;
    }
}

/// Poisson samples by inversion (poisson_by_inversion's sums, in float), 64 values at a time,
/// for the values with a uniform (the others, uniform 0, stop at once and keep their Gaussian
/// electrons). Each stops at mean + 8 sqrt(mean) + 8 at the most: where float sums could
/// fail to reach a uniform within 1e-6 of 1, the tail is cut there (probability below 1e-7).
DEEPSEA_CAMERA_CLONES
void invert_exact(int m, const float* mean, const float* uniform, float* electrons) {
    for (int j0 = 0; j0 < m; j0 += 64) {
        const int len = j0 + 64 < m ? 64 : m - j0;
        const float* mu = mean + j0;
        const float* u = uniform + j0;
        float p[64], cdf[64], k[64], cap[64];
#pragma omp simd
        for (int j = 0; j < len; ++j) {
            p[j] = std::exp(-mu[j]);
            cdf[j] = p[j];
            k[j] = 0.0f;
            cap[j] = mu[j] + 8.0f * std::sqrt(mu[j]) + 8.0f;
        }
        for (int it = 1; it <= 128; ++it) {
            const float inv = kInv.r[it];
            int any = 0;
#pragma omp simd reduction(| : any)
            for (int j = 0; j < len; ++j) {
                const int go = u[j] > cdf[j] && k[j] < cap[j];
                k[j] += float(go);
                p[j] *= mu[j] * inv;
                cdf[j] += p[j];
                any |= go;
            }
            if (!any) break;
        }
        for (int j = 0; j < len; ++j)
            if (u[j] > 0.0f) electrons[j0 + j] = k[j];
    }
}

/// The exact path for the m values listed in b.index: the Poisson below kGaussianShotNoiseFrom
/// electrons, and near the full well the shot noise clipped before the read noise adds.
/// Gathered, computed in vector loops, scattered back.
void exact_values(const SensorParams& p, std::uint32_t base, int m, const RowBuffers& b) {
    gather_exact(p, base, m, b);
    invert_exact(m, b.exact_mean, b.exact_uniform, b.exact_electrons);
    for (int j = 0; j < m; ++j) {
        const int i = b.index[j];
        const float electrons = b.exact_electrons[j], offset = b.exact_offset[j];
        const float dn = p.gain * (min_of(electrons, p.full_well) + offset) + p.black;
        b.raw[i] = min_of(max_of(std::floor(dn + 0.5f), 0.0f), p.max_dn);
        if (p.keep_linear) b.linear[i] = p.gain * (electrons + offset) + p.black;
    }
}

/// exact_values for the values flagged in b.flag.
void exact_path(const SensorParams& p, std::uint32_t base, int n, const RowBuffers& b) {
    int m = 0, i = 0;
    for (; i + 8 <= n; i += 8) {  // 8 flags at a time: most are 0
        const std::int32_t* f = b.flag + i;
        if ((f[0] | f[1] | f[2] | f[3] | f[4] | f[5] | f[6] | f[7]) == 0) continue;
        for (int j = i; j < i + 8; ++j) {
            b.index[m] = j;
            m += b.flag[j];
        }
    }
    for (; i < n; ++i) {
        b.index[m] = i;
        m += b.flag[i];
    }
    exact_values(p, base, m, b);
}

}  // namespace

DEEPSEA_CAMERA_CLONES
void gain_row(const Vignetting& vig, const float* x2, float y2, const float resp[3], int pixels,
              float* gain) {
    const float r = resp[0], g = resp[1], bl = resp[2];
#pragma omp simd
    for (int u = 0; u < pixels; ++u) {
        const float f = vignetting_factor(vig, x2[u] + y2);
        gain[3 * u] = f * r;
        gain[3 * u + 1] = f * g;
        gain[3 * u + 2] = f * bl;
    }
}

namespace {

/// The Gaussian (fast) path of sensor_row for every value; flags the ones for the exact path and
/// returns their count. kLinear: store the linear DN too; kMosaic: flag only recorded values.
template <bool kLinear, bool kMosaic>
[[gnu::always_inline]] inline int noisy_values(const SensorParams& p, int n, const RowBuffers& b) {
    const float t = p.exposure_time_ms, dark = p.dark_electrons, fw = p.full_well, K = p.gain;
    const float black = p.black, max_dn = p.max_dn, read_var = p.read_noise * p.read_noise;
    const float poisson_below = p.poisson_below;
    // Locals, so that the loop does not reload them after every store.
    const float* __restrict radiance = b.radiance;
    const float* __restrict response = b.response;
    const float* __restrict dsnu = b.dsnu;
    const std::int32_t* __restrict record = b.record;
    const float* __restrict normal = b.normal;
    float* __restrict mean_out = b.mean;
    std::int32_t* __restrict flag = b.flag;
    float* __restrict raw = b.raw;
    float* __restrict linear = b.linear;
    int exact = 0;
#pragma omp simd reduction(+ : exact)
    for (int i = 0; i < n; ++i) {
        const float mean = max_of(radiance[i], 0.0f) * response[i] * t + dark;
        // Shot and read noise are independent here: one deviate of their summed variance.
        // One reciprocal square root (vrsqrtps and a Newton step under -ffast-math) gives both
        // sigma and Cornish-Fisher's b = mean / (6 sigma^2): no division. Where variance is 0
        // (mean 0, no read noise) the value takes the exact path below.
        const float variance = mean + read_var, r = 1.0f / std::sqrt(variance);
        const float sigma = variance * r;
        const float z = normal[i];
        const float skew = mean * (r * r) * (1.0f / 6.0f) * (z * z - 1.0f);
        const float dn = K * (mean + sigma * z + skew + dsnu[i]) + black;
        raw[i] = min_of(max_of(std::floor(dn + 0.5f), 0.0f), max_dn);
        if constexpr (kLinear) linear[i] = dn;
        mean_out[i] = mean;
        std::int32_t slow = mean < poisson_below || mean + kClipReach * sigma >= fw;
        if constexpr (kMosaic) slow &= record[i];
        flag[i] = slow;
        exact += slow;
    }
    return exact;
}

/// With a mosaic, the values a pixel does not record read out 0.
[[gnu::always_inline]] inline void mask(const std::int32_t* record, int n, float* values) {
    const std::int32_t* __restrict r = record;
    float* __restrict x = values;
#pragma omp simd
    for (int i = 0; i < n; ++i) x[i] = r[i] ? x[i] : 0.0f;
}

}  // namespace

DEEPSEA_CAMERA_CLONES
void sensor_row(const SensorParams& p, std::uint32_t base, int n, const RowBuffers& b) {
    const float t = p.exposure_time_ms, dark = p.dark_electrons, fw = p.full_well, K = p.gain;
    const float black = p.black, max_dn = p.max_dn;
    if (!p.noise) {
        const float* __restrict radiance = b.radiance;
        const float* __restrict response = b.response;
        float* __restrict raw = b.raw;
        float* __restrict linear = b.linear;
        const bool keep_linear = p.keep_linear;
#pragma omp simd
        for (int i = 0; i < n; ++i) {
            const float mean = max_of(radiance[i], 0.0f) * response[i] * t + dark;
            const float dn = K * min_of(mean, fw) + black;
            raw[i] = min_of(max_of(std::floor(dn + 0.5f), 0.0f), max_dn);
            if (keep_linear) linear[i] = K * mean + black;
        }
    } else {
        // Four loops (linear kept or not, mosaic or not): the plain one carries no mask.
        normal_row(p.shot_key, base, n, b.normal, b.index);
        const bool lin = p.keep_linear, mos = b.record != nullptr;
        if (reads_unaligned(p, mos)) {  // lists the exact path's values itself
            const int m = gaussian_values_avx2(p, n, b);
            if (!m) return;
            exact_values(p, base, m, b);
            const std::int32_t* chan = chunk_channels();
            for (int j = 0; j < m; ++j) {  // the image of the values the exact path changed
                const int i = b.index[j], at = 3 * std::int32_t(b.raw[i]) + chan[i];
                if (b.shown) b.shown[i] = b.lut[at];
                if (b.codes) b.codes[i] = b.code_lut[at];
            }
            return;
        }
        const int exact =
            lin ? (mos ? noisy_values<true, true>(p, n, b) : noisy_values<true, false>(p, n, b))
                : (mos ? noisy_values<false, true>(p, n, b) : noisy_values<false, false>(p, n, b));
        if (exact) exact_path(p, base, n, b);
    }
    if (!b.record) return;
    mask(b.record, n, b.raw);
    if (p.keep_linear) mask(b.record, n, b.linear);
}

DEEPSEA_CAMERA_CLONES
void fixed_pattern_row(NoiseKey prnu_key, NoiseKey dsnu_key, std::uint32_t base, int n, float prnu,
                       float dsnu, float* response, float* dsnu_out) {
    alignas(64) float z[kChunk];
    alignas(64) std::int32_t index[kChunk];
    for (int c0 = 0; c0 < n; c0 += kChunk) {  // chunks from the row's start, as sensor_row's
        const int len = c0 + kChunk < n ? kChunk : n - c0;
        float* __restrict r = response + c0;
        if (prnu > 0.0f) {
            normal_row(prnu_key, base + std::uint32_t(c0), len, z, index);
#pragma omp simd
            for (int i = 0; i < len; ++i) r[i] = max_of(0.0f, r[i] * (1.0f + prnu * z[i]));
        }
        if (!dsnu_out) continue;
        float* __restrict d = dsnu_out + c0;
        normal_row(dsnu_key, base + std::uint32_t(c0), len, z, index);
#pragma omp simd
        for (int i = 0; i < len; ++i) d[i] = dsnu * z[i];
    }
}

DEEPSEA_CAMERA_CLONES
void noise_free_row(const SensorParams& p, int n, const float* radiance, const float* response,
                    float* dn) {
    const float t = p.exposure_time_ms, dark = p.dark_electrons, fw = p.full_well, K = p.gain;
    const float black = p.black, max_dn = p.max_dn;
#pragma omp simd
    for (int i = 0; i < n; ++i) {
        const float mean = max_of(radiance[i], 0.0f) * response[i] * t + dark;
        dn[i] = min_of(K * min_of(mean, fw) + black, max_dn);
    }
}

namespace {

/// One variant of the processing loops, inlined into process_row's clones.
template <bool kMatrix, OutputCurve kCurve>
[[gnu::always_inline]] inline void process(const ProcessParams& p, int n, const float* scale,
                                           const float* dn, float* tmp, float* out) {
    const float black = p.black, inv_gamma = p.inv_gamma;
#pragma omp simd
    for (int i = 0; i < n; ++i) tmp[i] = (dn[i] - black) * scale[i];
    if constexpr (kMatrix) {
        const float m0 = p.m[0], m1 = p.m[1], m2 = p.m[2], m3 = p.m[3], m4 = p.m[4], m5 = p.m[5],
                    m6 = p.m[6], m7 = p.m[7], m8 = p.m[8];
#pragma omp simd
        for (int u = 0; u < n / 3; ++u) {
            const float x = tmp[3 * u], y = tmp[3 * u + 1], z = tmp[3 * u + 2];
            tmp[3 * u] = m0 * x + m1 * y + m2 * z;
            tmp[3 * u + 1] = m3 * x + m4 * y + m5 * z;
            tmp[3 * u + 2] = m6 * x + m7 * y + m8 * z;
        }
    }
#pragma omp simd
    for (int i = 0; i < n; ++i) {
        const float x = min_of(max_of(tmp[i], 0.0f), 1.0f);
        if constexpr (kCurve == OutputCurve::Srgb)
            out[i] = srgb_curve(x);
        else if constexpr (kCurve == OutputCurve::Gamma)
            out[i] = gamma_encode(x, inv_gamma);
        else
            out[i] = x;
    }
}

template <bool kMatrix>
[[gnu::always_inline]] inline void process_curve(const ProcessParams& p, int n, const float* scale,
                                                 const float* dn, float* tmp, float* out) {
    switch (p.curve) {
        case OutputCurve::Srgb:
            return process<kMatrix, OutputCurve::Srgb>(p, n, scale, dn, tmp, out);
        case OutputCurve::Gamma:
            return process<kMatrix, OutputCurve::Gamma>(p, n, scale, dn, tmp, out);
        case OutputCurve::Linear:
            break;
    }
    process<kMatrix, OutputCurve::Linear>(p, n, scale, dn, tmp, out);
}

DEEPSEA_CAMERA_CLONES
void brightest_generic(int p0, int pixels, const float* raw, std::int32_t last, std::int32_t* bin) {
#pragma omp simd
    for (int p = p0; p < pixels; ++p) {
        const std::int32_t b =
            std::int32_t(max_of(raw[3 * p], max_of(raw[3 * p + 1], raw[3 * p + 2])));
        bin[p] = b < last ? b : last;
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
/// 8 pixels from 3 vectors (24 interleaved values) at a time: blends put each pixel's R, G and B
/// in the same lane of three vectors (pixels in the order 0 3 6 1 4 7 2 5, G and B rotated into
/// it), two maxima, one permute back to pixel order (GCC's vectoriser makes the strided loads of
/// brightest_generic with twice the instructions).
__attribute__((target("avx2"))) void brightest_avx2(int pixels, const float* raw, std::int32_t last,
                                                    std::int32_t* bin) {
    const __m256i g_turn = _mm256_setr_epi32(1, 2, 3, 4, 5, 6, 7, 0);
    const __m256i b_turn = _mm256_setr_epi32(2, 3, 4, 5, 6, 7, 0, 1);
    const __m256i order = _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5);  // lane of pixel k
    const __m256i top = _mm256_set1_epi32(last);
    int p = 0;
    for (; p + 8 <= pixels; p += 8) {
        const float* q = raw + 3 * p;
        const __m256 a = _mm256_loadu_ps(q), b = _mm256_loadu_ps(q + 8),
                     c = _mm256_loadu_ps(q + 16);
        // Lane l of r: value 0 9 18 3 12 21 6 15 (R of pixels 0 3 6 1 4 7 2 5).
        const __m256 r = _mm256_blend_ps(_mm256_blend_ps(a, b, 0x92), c, 0x24);
        // Before turning: C0 A1 B2 C3 A4 B5 C6 A7 and B0 C1 A2 B3 C4 A5 B6 C7.
        const __m256 g =
            _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(a, b, 0x24), c, 0x49), g_turn);
        const __m256 bl =
            _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(a, b, 0x49), c, 0x92), b_turn);
        const __m256 m = _mm256_permutevar8x32_ps(_mm256_max_ps(r, _mm256_max_ps(g, bl)), order);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(bin + p),
                            _mm256_min_epi32(_mm256_cvttps_epi32(m), top));
    }
    brightest_generic(p, pixels, raw, last, bin);
}
/// The AVX2 loops here and below are taken where the processor has AVX2.
const bool kHaveAvx2 = __builtin_cpu_supports("avx2");
#endif

}  // namespace

void brightest_row(int pixels, const float* raw, std::int32_t last, std::int32_t* bin) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (kHaveAvx2) return brightest_avx2(pixels, raw, last, bin);
#endif
    brightest_generic(0, pixels, raw, last, bin);
}

DEEPSEA_CAMERA_CLONES
void process_row(const ProcessParams& p, int n, const float* scale, const float* dn, float* tmp,
                 float* out) {
    if (p.matrix)
        process_curve<true>(p, n, scale, dn, tmp, out);
    else
        process_curve<false>(p, n, scale, dn, tmp, out);
}

#if defined(__x86_64__) && defined(__GNUC__)
/// The table read with AVX2's vgatherdps, 8 values at a time (written by hand: GCC's
/// vectoriser will not emit gathers for this loop under its generic tuning and emulates them
/// with 8 scalar loads and inserts, which measured no faster than scalar code).
__attribute__((target("avx2"))) void lookup_avx2(const float* lut, int n, const float* dn,
                                                 float* out) {
    const std::int32_t* chan = kChannels.c;
    int i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256i d = _mm256_cvttps_epi32(_mm256_load_ps(dn + i));
        const __m256i at =
            _mm256_add_epi32(_mm256_add_epi32(d, _mm256_slli_epi32(d, 1)),
                             _mm256_load_si256(reinterpret_cast<const __m256i*>(chan + i)));
        _mm256_storeu_ps(out + i, _mm256_i32gather_ps(lut, at, 4));
    }
    for (; i < n; ++i) out[i] = lut[3 * std::int32_t(dn[i]) + chan[i]];
}
__attribute__((target("avx2"))) void lookup_codes_avx2(const std::uint8_t* lut, int n,
                                                       const float* dn, std::uint8_t* out) {
    const std::int32_t* chan = kChannels.c;
    int i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256i d = _mm256_cvttps_epi32(_mm256_load_ps(dn + i));
        const __m256i at =
            _mm256_add_epi32(_mm256_add_epi32(d, _mm256_slli_epi32(d, 1)),
                             _mm256_load_si256(reinterpret_cast<const __m256i*>(chan + i)));
        read_codes(lut, at, out + i);
    }
    for (; i < n; ++i) out[i] = lut[3 * std::int32_t(dn[i]) + chan[i]];
}
#endif

void lookup_row(const float* lut, int n, const float* dn, float* out) {
    // A whole DN converts to its index exactly; a table read gives the same bits whichever lanes
    // or scalar code read it.
#if defined(__x86_64__) && defined(__GNUC__)
    if (kHaveAvx2) return lookup_avx2(lut, n, dn, out);
#endif
    for (int i = 0; i < n; i += 3) {
        out[i] = lut[3 * std::int32_t(dn[i])];
        out[i + 1] = lut[3 * std::int32_t(dn[i + 1]) + 1];
        out[i + 2] = lut[3 * std::int32_t(dn[i + 2]) + 2];
    }
}

void lookup_codes_row(const std::uint8_t* lut, int n, const float* dn, std::uint8_t* out) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (kHaveAvx2) return lookup_codes_avx2(lut, n, dn, out);
#endif
    for (int i = 0; i < n; i += 3)
        for (int c = 0; c < 3; ++c) out[i + c] = lut[3 * std::int32_t(dn[i + c]) + c];
}

}  // namespace deepsea::camera_rows
