#pragma once
/// \file The sensor's random numbers (docs/noise.md): counter-based, so that a pixel's
/// noise depends only on (seed, frame key, pixel, channel), never on the order of frames, the
/// thread count or which rows a thread ran. Fixed patterns (DSNU, PRNU) are keyed by the seed
/// and the pixel only: the same in every frame of one camera. Each stream's key comes from
/// core's SplitMix64 (random.h); each value's bits from a 32-bit hash of its counter.

#include <cmath>
#include <cstdint>
#include <cstring>

#include "deepsea/core/fast_math.h"
#include "deepsea/core/random.h"

namespace deepsea {

/// Photon shot noise is drawn from the Poisson distribution (by inversion) when its mean is
/// below this many electrons. At and above it, from a normal deviate z with the Poisson's
/// first three moments (Cornish-Fisher): mean + sigma z + b (z^2 - 1), b = mean / (6 sigma^2),
/// sigma^2 = mean (+ the read noise's variance where the two are drawn as one): its variance
/// exceeds the Poisson's by 2 b^2 <= 1/18 electron^2 (0.35 % at 16 electrons), its skewness is
/// the Poisson's 1 / sqrt(mean), and it is not rounded to whole electrons.
inline constexpr double kGaussianShotNoiseFrom = 16.0;

/// ... or at any mean where the read noise is at least this many electrons rms: the sum of a
/// Poisson count and such a read noise is so smooth that the Cornish-Fisher deviate of the two
/// (mean mu, variance mu + sigma_d^2, the Poisson's skewness term) has a distribution within
/// kGaussianSumKs of the exact sum's (Kolmogorov distance, the largest difference of the two
/// CDFs, at every mean; tests/unit/camera/emva_test.cpp computes it by convolution). Every
/// preset's read noise is above it; a camera with less read noise keeps the Poisson path
/// below kGaussianShotNoiseFrom.
inline constexpr double kGaussianReadNoiseFrom = 2.0;
inline constexpr double kGaussianSumKs = 1e-3;

/// The mean below which shot noise takes the Poisson path, for a read noise (electrons rms).
inline double poisson_below(double read_noise) {
    return read_noise >= kGaussianReadNoiseFrom ? 0.0 : kGaussianShotNoiseFrom;
}

/// Cornish-Fisher's skewness term's factor b for a Poisson mean within a total variance.
template <class F>
[[gnu::always_inline]] inline F skew_factor(F mean, F variance) {
    return mean / (F(6) * variance);
}

/// The random numbers' streams: each draws its own 32 bits per value.
enum class NoiseStream : std::uint64_t {
    Prnu = 1,  ///< fixed pattern: photo-response non-uniformity
    Dsnu = 2,  ///< fixed pattern: dark signal non-uniformity
    Shot = 3,  ///< temporal: shot noise (with read noise in one Gaussian where they add)
    Read = 4,  ///< temporal: read noise where it is drawn on its own
};

/// The key of one stream: the counter is scrambled as counter * mul + add (mod 2^32, mul
/// odd: a bijection), then hashed.
struct NoiseKey {
    std::uint32_t mul = 1, add = 0;
};

/// A stream's key from a 64-bit seed (core's SplitMix64).
inline NoiseKey noise_key(std::uint64_t seed64) {
    Rng rng(seed64);
    const std::uint64_t b = rng.next();
    return {std::uint32_t(b) | 1u, std::uint32_t(b >> 32)};
}

/// A fixed-pattern stream of a camera: the seed alone, the same in every frame.
inline NoiseKey fixed_pattern_key(std::uint64_t seed, NoiseStream s) {
    return noise_key(mix_seed(seed, 0x66697865645f7061ull /* "fixed_pa" */, std::uint64_t(s)));
}

/// A temporal stream of one frame: (seed, frame key).
inline NoiseKey temporal_key(std::uint64_t seed, std::uint64_t frame_key, NoiseStream s) {
    return noise_key(mix_seed(seed, frame_key, std::uint64_t(s)));
}

/// C. Wellons' "triple32" integer hash (2018; its measured avalanche bias, 0.021, is among
/// the lowest of 32-bit hashes): 3 multiplies, vectorised natively (AVX2 vpmulld), where
/// SplitMix64's 64-bit multiplies are emulated in three.
[[gnu::always_inline]] inline std::uint32_t triple32(std::uint32_t x) {
    x ^= x >> 17;
    x *= 0xed5ad4bbu;
    x ^= x >> 11;
    x *= 0xac4c1b51u;
    x ^= x >> 15;
    x *= 0x31848babu;
    x ^= x >> 14;
    return x;
}

/// The counter of channel c (0 R, 1 G, 2 B) of pixel (u, v) in a width-wide image:
/// 3 (v width + u) + c, below 2^32 for every image deepsea accepts (kMaxImagePixels).
inline std::uint32_t noise_counter(int width, int u, int v, int c) {
    return std::uint32_t(3 * (std::uint64_t(v) * std::uint64_t(width) + std::uint64_t(u)) +
                         std::uint64_t(c));
}

/// 32 random bits of a stream for a counter: triple32(counter * mul + add).
[[gnu::always_inline]] inline std::uint32_t noise_bits(NoiseKey k, std::uint32_t counter) {
    return triple32(counter * k.mul + k.add);
}

/// The lower half's uniform of 32 random bits: t = (2 i + 1) / 2^25 in (0, 1/2), i = bits 8-30
/// (23 bits; bit 31 is the deviate's sign). Exact in float: 2 i + 1 < 2^24.
template <class F>
[[gnu::always_inline]] inline F normal_half_uniform(std::uint32_t bits) {
    return F(std::int32_t((bits >> 8) & 0x7fffffu)) * F(1.0 / 16777216.0) + F(1.0 / 33554432.0);
}

/// The inverse normal CDF's table: on each octave j of t (t in [2^-(j+2), 2^-(j+1)), j 0 to 7,
/// t >= 2^-9) a degree-4 polynomial in y = m - 1.5, m in [1, 2) the float mantissa of t
/// (t = m 2^-(j+2)): kNormalTable[k][j] is the coefficient of y^k. Chebyshev interpolation of
/// Phi^-1 at 5 nodes per octave (Python's statistics.NormalDist.inv_cdf): within
/// kNormalTableError of Phi^-1(t) everywhere (tests/unit/camera/normal_test.cpp).
inline constexpr int kNormalOctaves = 8;
inline constexpr float kNormalTable[5][kNormalOctaves] = {
    {-3.186393640e-01f, -8.871465590e-01f, -1.318010897e+00f, -1.675939723e+00f, -1.987427886e+00f,
     -2.266226809e+00f, -2.520502217e+00f, -2.755548873e+00f},
    {6.590257278e-01f, 4.641842332e-01f, 3.732037915e-01f, 3.188555910e-01f, 2.820551836e-01f,
     2.551586071e-01f, 2.344612967e-01f, 2.179324898e-01f},
    {-6.912312835e-02f, -9.554549707e-02f, -9.177566819e-02f, -8.519292352e-02f, -7.905721830e-02f,
     -7.377731365e-02f, -6.928526168e-02f, -6.544447921e-02f},
    {6.162705541e-02f, 4.650625549e-02f, 4.208919704e-02f, 3.885506766e-02f, 3.619317259e-02f,
     3.395436419e-02f, 3.204779003e-02f, 3.040564994e-02f},
    {-2.108436026e-02f, -2.207923035e-02f, -2.038339808e-02f, -1.891968973e-02f, -1.769069042e-02f,
     -1.664950273e-02f, -1.575750321e-02f, -1.498490073e-02f},
};
/// The table's largest error in standard deviations (3.56e-5 at the interpolation's worst
/// point), so its deviates' CDF is within 0.4 x 3.6e-5 = 1.5e-5 of the normal's.
inline constexpr double kNormalTableError = 3.6e-5;

/// Giles' central branch: sqrt(2) erfinv(x) for w < 5.
template <class F>
[[gnu::always_inline]] inline F normal_central(F x, F w) {
    const F a = w - F(2.5);
    F p = F(2.81022636e-08);
    p = F(3.43273939e-07) + p * a;
    p = F(-3.5233877e-06) + p * a;
    p = F(-4.39150654e-06) + p * a;
    p = F(0.00021858087) + p * a;
    p = F(-0.00125372503) + p * a;
    p = F(-0.00417768164) + p * a;
    p = F(0.246640727) + p * a;
    p = F(1.50140941) + p * a;
    return F(1.41421356237309505) * p * x;
}

/// Giles' tail branch: sqrt(2) erfinv(x) for w >= 5.
template <class F>
[[gnu::always_inline]] inline F normal_tail(F x, F w) {
    const F b = std::sqrt(w) - F(3);
    F q = F(-0.000200214257);
    q = F(0.000100950558) + q * b;
    q = F(0.00134934322) + q * b;
    q = F(-0.00367342844) + q * b;
    q = F(0.00573950773) + q * b;
    q = F(-0.0076224613) + q * b;
    q = F(0.00943887047) + q * b;
    q = F(1.00167406) + q * b;
    q = F(2.83297682) + q * b;
    return F(1.41421356237309505) * q * x;
}

/// Phi^-1(t) for t in (0, 1/2) below the table (t < 2^-9, 0.39 % of deviates): M. Giles'
/// single-precision erfinv ("Approximating the erfinv function", GPU Computing Gems Jade, 2011;
/// relative error below 4e-7): -sqrt(2) erfinv(x), x = 1 - 2t, 1 - x^2 = 4 t (1 - t).
template <class F>
[[gnu::always_inline]] inline F normal_tail_of(F t) {
    const F x = F(1) - F(2) * t, w = -fast_log(F(4) * t * (F(1) - t));
    return -(w < F(5) ? normal_central(x, w) : normal_tail(x, w));
}

/// The octave of t's table, 0 to 7, or more below the table (the float exponent of t).
inline int normal_octave(float t) {
    std::uint32_t b;
    std::memcpy(&b, &t, sizeof b);
    return 125 - int(b >> 23);
}

/// A standard normal deviate from 32 random bits (24 used: a sign and 23 for t, as
/// normal_half_uniform): Phi^-1(t), negated when bit 31 is set. For t >= 2^-9 (99.61 % of
/// deviates) from the octave table (kNormalTable), below it from Giles' erfinv. So the mean is
/// exactly 0 (the sign is a bit of its own) and the tails end at Phi^-1(2^-25) = -+5.42
/// sigma. In double (the tests' reference) the same table and the same t.
template <class F>
[[gnu::always_inline]] inline F normal_from_bits(std::uint32_t bits) {
    const float tf = normal_half_uniform<float>(bits);
    const F t = normal_half_uniform<F>(bits);
    const int j = normal_octave(tf);
    F p;
    if (j < kNormalOctaves) {
        std::uint32_t b;
        std::memcpy(&b, &tf, sizeof b);
        const std::uint32_t mb = (b & 0x7fffffu) | 0x3f800000u;
        float m;
        std::memcpy(&m, &mb, sizeof m);
        const F y = F(m) - F(1.5);
        p = F(kNormalTable[4][j]);
        for (int k = 3; k >= 0; --k) p = F(kNormalTable[k][j]) + p * y;
    } else {
        p = normal_tail_of(t);
    }
    return bits >> 31 ? -p : p;
}

/// normal_from_bits for bits whose t lies below the table (normal_octave(t) >= 8): the tail
/// alone, without the table's branch, so that loops over gathered tails vectorise.
template <class F>
[[gnu::always_inline]] inline F normal_tail_from_bits(std::uint32_t bits) {
    const F p = normal_tail_of(normal_half_uniform<F>(bits));
    return bits >> 31 ? -p : p;
}

/// A uniform number in (0, 1) from 32 random bits: (bits + 1/2) / 2^32.
inline double uniform_from_bits(std::uint32_t bits) {
    return (double(bits) + 0.5) * (1.0 / 4294967296.0);
}

/// The Poisson sample of mean `mean` (>= 0) that uniform u in (0, 1) gives by inversion: the
/// smallest k with P(X <= k) >= u, summing p(k) = p(k - 1) mean / k from p(0) = exp(-mean).
/// At most `max_k` (beyond it lies less probability than u resolves for means below
/// kGaussianShotNoiseFrom).
inline int poisson_by_inversion(double mean, double u, int max_k = 128) {
    double p = std::exp(-mean), cdf = p;
    int k = 0;
    while (u > cdf && k < max_k) {
        ++k;
        p *= mean / k;
        cdf += p;
    }
    return k;
}

}  // namespace deepsea
