#pragma once
/// \file Integer hashing and 2-D gradient noise for the procedural seafloor (internal).
/// Everything here is plain integer and IEEE arithmetic (no libm transcendental calls, no
/// std::rand or std distributions), so a seed gives the same seafloor bit for bit with any
/// standard library and at any thread count.

#include <cmath>
#include <cstdint>

namespace deepsea::scene_detail {

/// Avalanching 64-bit mix: every input bit flips about half the output bits, which lets
/// neighbouring lattice cells get unrelated random values.
inline std::uint64_t mix64(std::uint64_t z) {
    z ^= z >> 32;
    z *= 0xd6e8feb86659fd93ULL;
    z ^= z >> 29;
    z *= 0xa3b195354a39b70dULL;
    z ^= z >> 32;
    return z;
}

/// Hash of a lattice cell (ix, iy) under a per-layer salt. One mix of a linear combination is
/// enough: two cells collide only if their coordinate differences satisfy one congruence mod
/// 2^64, which no pair within billions of cells of each other does in practice.
inline std::uint64_t hash_cell(std::uint64_t salt, std::int64_t ix, std::int64_t iy) {
    return mix64(salt + std::uint64_t(ix) * 0x9e3779b97f4a7c15ULL +
                 std::uint64_t(iy) * 0xc2b2ae3d27d4eb4fULL);
}

/// Uniform in [0, 1) from the top 53 bits of a hash. (Through int64: x86-64 has no direct
/// unsigned 64-bit to double conversion.)
inline double unit(std::uint64_t h) {
    return double(std::int64_t(h >> 11)) * (1.0 / 9007199254740992.0);
}

/// Uniform in [0, 1) from `bits` bits of a hash starting at bit `shift`: several cheap values
/// from one hash where a few thousand levels are plenty.
inline double bits_unit(std::uint64_t h, int shift, int bits) {
    const auto v = std::int64_t((h >> shift) & ((std::uint64_t(1) << bits) - 1));
    return double(v) * (1.0 / double(std::int64_t(1) << bits));
}

/// floor() for |x| < 2^62 without a libm call (baseline x86-64 has no rounding instruction,
/// and this runs several times per noise value). Exact: truncation, then one correction.
inline double fast_floor(double x) {
    const double t = double(std::int64_t(x));
    return t > x ? t - 1.0 : t;
}

/// The k-th independent uniform value of one cell: re-mixes the cell hash with k.
inline double cell_unit(std::uint64_t cell_hash, std::uint64_t k) {
    return unit(mix64(cell_hash + k * 0x632be59bd9b4e019ULL));
}

/// Salt of layer `layer` for a seed: different layers of one seafloor stay uncorrelated.
inline std::uint64_t layer_salt(std::uint64_t seed, std::uint64_t layer) {
    return mix64(mix64(seed ^ 0x5851f42d4c957f2dULL) + layer * 0x8a5cd789635d2dffULL);
}

/// Quintic fade 6t^5 - 15t^4 + 10t^3: C2 continuous, so shading from the depth map's normals
/// shows no lattice lines.
inline double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

inline double lerp(double a, double b, double t) { return a + (b - a) * t; }

/// Eight unit gradient directions, written out so that no cos/sin is needed.
inline constexpr double kGradX[8] = {1.0,
                                     -1.0,
                                     0.0,
                                     0.0,
                                     0.70710678118654752,
                                     0.70710678118654752,
                                     -0.70710678118654752,
                                     -0.70710678118654752};
inline constexpr double kGradY[8] = {0.0,
                                     0.0,
                                     1.0,
                                     -1.0,
                                     0.70710678118654752,
                                     -0.70710678118654752,
                                     0.70710678118654752,
                                     -0.70710678118654752};

/// Gradient directions (indices into kGradX/Y) at the four corners of one lattice cell.
struct NoiseCorners {
    unsigned g00 = 0, g10 = 0, g01 = 0, g11 = 0;
};

inline NoiseCorners noise_corners(std::uint64_t salt, std::int64_t ix, std::int64_t iy) {
    return {unsigned(hash_cell(salt, ix, iy) >> 61), unsigned(hash_cell(salt, ix + 1, iy) >> 61),
            unsigned(hash_cell(salt, ix, iy + 1) >> 61),
            unsigned(hash_cell(salt, ix + 1, iy + 1) >> 61)};
}

/// The noise inside one cell at offset (dx, dy) in [0, 1)^2 from its lower corner.
inline double noise_in_cell(const NoiseCorners& c, double dx, double dy) {
    const double n00 = kGradX[c.g00] * dx + kGradY[c.g00] * dy;
    const double n10 = kGradX[c.g10] * (dx - 1.0) + kGradY[c.g10] * dy;
    const double n01 = kGradX[c.g01] * dx + kGradY[c.g01] * (dy - 1.0);
    const double n11 = kGradX[c.g11] * (dx - 1.0) + kGradY[c.g11] * (dy - 1.0);
    const double u = fade(dx), v = fade(dy);
    return lerp(lerp(n00, n10, u), lerp(n01, n11, u), v);
}

/// 2-D gradient noise with unit lattice spacing: zero at lattice points, |value| < kNoiseMax,
/// |gradient| < kNoiseSlope.
inline double gradient_noise(std::uint64_t salt, double x, double y) {
    const double fx = fast_floor(x), fy = fast_floor(y);
    return noise_in_cell(noise_corners(salt, std::int64_t(fx), std::int64_t(fy)), x - fx, y - fy);
}

/// gradient_noise that remembers the corners of the last cell it looked up: the same values
/// (the same arithmetic), at about a third of the cost while successive points stay in one
/// cell, as a ray's last steps and refinements do.
class NoiseCache {
public:
    double operator()(std::uint64_t salt, double x, double y) {
        const double fx = fast_floor(x), fy = fast_floor(y);
        const auto ix = std::int64_t(fx), iy = std::int64_t(fy);
        if (!m_valid || ix != m_ix || iy != m_iy || salt != m_salt) {
            m_corners = noise_corners(salt, ix, iy);
            m_ix = ix;
            m_iy = iy;
            m_salt = salt;
            m_valid = true;
        }
        return noise_in_cell(m_corners, x - fx, y - fy);
    }

private:
    NoiseCorners m_corners;
    std::int64_t m_ix = 0, m_iy = 0;
    std::uint64_t m_salt = 0;
    bool m_valid = false;
};

/// Bound on |grad gradient_noise| (unit lattice): the largest value found over 4 million random
/// points was 2.003; 10 % margin. The ray marcher's step size relies on it (tests check it).
inline constexpr double kNoiseSlope = 2.2;
/// Bound on |gradient_noise|: sqrt(1/2) = 0.7071 for unit gradients, plus margin.
inline constexpr double kNoiseMax = 0.75;

/// Fractal sum of `octaves` octaves of noise(o, salt + o, x, y), each twice the frequency and
/// half the amplitude of the previous, rotated by an exact rational rotation (3-4-5 triangle)
/// so that the lattices of successive octaves do not line up. First octave amplitude 1.
template <class Noise>
double fbm_of(Noise&& noise, std::uint64_t salt, double x, double y, int octaves) {
    double sum = 0.0, amp = 1.0;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * noise(o, salt + std::uint64_t(o), x, y);
        const double rx = 0.8 * x - 0.6 * y, ry = 0.6 * x + 0.8 * y;
        x = 2.0 * rx + 17.31;
        y = 2.0 * ry - 5.77;
        amp *= 0.5;
    }
    return sum;
}

/// fbm_of gradient noise.
inline double fbm(std::uint64_t salt, double x, double y, int octaves) {
    return fbm_of(
        [](int, std::uint64_t s, double px, double py) { return gradient_noise(s, px, py); }, salt,
        x, y, octaves);
}

/// fbm with a NoiseCache per octave: the same values as fbm.
template <int Octaves>
class FbmCache {
public:
    double operator()(std::uint64_t salt, double x, double y) {
        return fbm_of(
            [this](int o, std::uint64_t s, double px, double py) { return m_cells[o](s, px, py); },
            salt, x, y, Octaves);
    }

private:
    NoiseCache m_cells[Octaves];
};

/// Sum of amplitudes of fbm (multiply by kNoiseMax for a value bound).
inline double fbm_amplitude(int octaves) {
    double sum = 0.0, amp = 1.0;
    for (int o = 0; o < octaves; ++o, amp *= 0.5) sum += amp;
    return sum;
}

/// Gradient bound of fbm in lattice units of the first octave: sum of amp * 2^o = octaves.
inline double fbm_slope(int octaves) { return kNoiseSlope * octaves; }

inline double clamp01(double v) { return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v); }

/// Hermite smoothstep from e0 to e1.
inline double smoothstep(double e0, double e1, double x) {
    const double t = clamp01((x - e0) / (e1 - e0));
    return t * t * (3.0 - 2.0 * t);
}

}  // namespace deepsea::scene_detail
