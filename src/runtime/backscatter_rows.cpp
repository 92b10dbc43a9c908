// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt); the looked-up rows'
// depth arrives sanitised (open water z == 0, never NaN or inf), as the compositor guarantees;
// the interpolated row's own is raw, tested on its bits.

#include "backscatter_rows.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "clones.h"
#include "deepsea/optics/normals.h"
#include "deepsea/runtime/sources.h"
#include "float4.h"

// (the Float8 values live in registers inside the clones: no call passes one)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace deepsea {

namespace {

/// Buckets of the nearest depth over [0, z_max]: the coefficients are taken at the slab of the
/// bucket's start, so finer buckets only loosen them where a group lies just beyond a boundary.
constexpr int kBuckets = 4096;

/// A depth as the lookup reads it (depth_slabs.h's cell): open water and beyond z_max, z_max.
[[gnu::always_inline]] inline float clamp_depth(float z, float z_max) {
    return z > 0.0f ? std::min(z, z_max) : z_max;
}

typedef std::int32_t Int8 __attribute__((vector_size(32)));

/// clamp_depth of raw planar depths, open water told by the floats' bits (optics'
/// has_surface: positive floats order as their bits, NaN and inf lie above kFarDepth's, -0
/// and negative values below 1), which fast-math cannot assume away as it may a NaN.
[[gnu::always_inline]] inline Float8 clamp_raw8(Float8 z, Float8 z_max, std::int32_t far_bits) {
    Int8 b;
    std::memcpy(&b, &z, sizeof b);
    return (b > 0) & (b < far_bits) ? (z_max < z ? z_max : z) : z_max;
}

[[gnu::always_inline]] inline float clamp_raw(float z, float z_max, std::int32_t far_bits) {
    std::int32_t b;
    std::memcpy(&b, &z, sizeof b);
    return (b > 0) & (b < far_bits) ? std::min(z, z_max) : z_max;
}

[[gnu::always_inline]] inline Float8 abs8(Float8 x) { return x < 0.0f ? -x : x; }
[[gnu::always_inline]] inline Float8 min8(Float8 a, Float8 b) { return b < a ? b : a; }

/// The coefficients of the bucket of a group's nearest depth (in [0, z_max]).
[[gnu::always_inline]] inline const BackscatterRowBounds::Coefficients& coefficients(
    const BackscatterRowBounds::Coefficients* buckets, int last, float scale, float nearest) {
    return buckets[std::min(int(nearest * scale), last)];
}

}  // namespace

void BackscatterSource::backscatter_pixels(int v, int n, const float* z, int count, const int* cols,
                                           float* out) const {
    thread_local std::vector<float> row;
    row.resize(3 * std::size_t(n));
    backscatter_row(v, n, z, row.data());
    for (int q = 0; q < count; ++q)
        std::copy_n(row.data() + 3 * std::size_t(cols[q]), 3, out + 3 * std::size_t(cols[q]));
}

BackscatterRowBounds backscatter_row_bounds(const Lattice& l, const float* values,
                                            double rows_per_step, int stride, double tol) {
    const int K = l.slabs(), nk = l.nk(), ni = l.ni, nj = l.nj;
    constexpr double inf = std::numeric_limits<double>::infinity();
    const auto S = [&](int i, int j, int k, int ch) {
        return double(values[((std::size_t(i) * nj + j) * nk + k) * 3 + ch]);
    };
    const auto at = [&](int i, int j, int k, int ch) {
        return ((std::size_t(i) * nj + j) * K + k) * 3 + ch;
    };
    // Per column, slab and channel: the slope and the smaller end (B's lower bound in the slab).
    std::vector<double> sig(std::size_t(ni) * nj * K * 3), m(sig.size()), mloc(sig.size());
    for (int i = 0; i < ni; ++i)
        for (int j = 0; j < nj; ++j)
            for (int k = 0; k < K; ++k)
                for (int ch = 0; ch < 3; ++ch) {
                    const double s0 = S(i, j, k, ch), s1 = S(i, j, k + 1, ch);
                    sig[at(i, j, k, ch)] = (s1 - s0) / (l.z[k + 1] - l.z[k]);
                    m[at(i, j, k, ch)] = std::min(s0, s1);
                }
    // The terms that compare neighbouring columns divide by the smallest B around (3 x 3): the
    // smallest of three along j, then of those along i (the same minimum, 6 comparisons not 9).
    std::vector<double> near_j(sig.size());
    for (int i = 0; i < ni; ++i)
        for (int j = 0; j < nj; ++j)
            for (int k = 0; k < K; ++k)
                for (int ch = 0; ch < 3; ++ch) {
                    double lo = m[at(i, j, k, ch)];
                    if (j > 0) lo = std::min(lo, m[at(i, j - 1, k, ch)]);
                    if (j + 1 < nj) lo = std::min(lo, m[at(i, j + 1, k, ch)]);
                    near_j[at(i, j, k, ch)] = lo;
                }
    for (int i = 0; i < ni; ++i)
        for (int j = 0; j < nj; ++j)
            for (int k = 0; k < K; ++k)
                for (int ch = 0; ch < 3; ++ch) {
                    double lo = near_j[at(i, j, k, ch)];
                    if (i > 0) lo = std::min(lo, near_j[at(i - 1, j, k, ch)]);
                    if (i + 1 < ni) lo = std::min(lo, near_j[at(i + 1, j, k, ch)]);
                    mloc[at(i, j, k, ch)] = lo;
                }
    // Each difference that two neighbours share, once: the slope's change from slab k to k + 1
    // (kinks), from lattice row j to j + 1 per image row (rows), and B's second difference
    // across lattice row j at depth sample q per image row (curves; interior rows only).
    std::vector<double> kinks(sig.size()), rows(sig.size()), curves(std::size_t(ni) * nj * nk * 3);
    const auto at_q = [&](int i, int j, int q, int ch) {
        return ((std::size_t(i) * nj + j) * nk + q) * 3 + ch;
    };
    for (int i = 0; i < ni; ++i)
        for (int j = 0; j < nj; ++j) {
            for (int k = 0; k < K; ++k)
                for (int ch = 0; ch < 3; ++ch) {
                    const double s = sig[at(i, j, k, ch)];
                    if (k + 1 < K) kinks[at(i, j, k, ch)] = std::fabs(sig[at(i, j, k + 1, ch)] - s);
                    if (j + 1 < nj)
                        rows[at(i, j, k, ch)] =
                            std::fabs(sig[at(i, j + 1, k, ch)] - s) / rows_per_step;
                }
            if (j > 0 && j + 1 < nj)
                for (int q = 0; q < nk; ++q)
                    for (int ch = 0; ch < 3; ++ch) {
                        const double d2 =
                            S(i, j + 1, q, ch) - 2.0 * S(i, j, q, ch) + S(i, j - 1, q, ch);
                        curves[at_q(i, j, q, ch)] = std::fabs(d2) / rows_per_step;
                    }
        }
    std::vector<double> A(K, 0.0), C(K, 0.0), T(K, 0.0), reach(K, 0.0);
    for (int i = 0; i < ni; ++i)
        for (int j = 0; j < nj; ++j)
            for (int k = 0; k < K; ++k)
                for (int ch = 0; ch < 3; ++ch) {
                    const double s = sig[at(i, j, k, ch)], own = m[at(i, j, k, ch)];
                    const double lo = mloc[at(i, j, k, ch)];
                    A[k] = std::max(A[k], own > 0.0 ? std::fabs(s) / own : inf);
                    // a boundary crossed: the slope changes there
                    double kink = 0.0;
                    if (k > 0) kink = kinks[at(i, j, k - 1, ch)];
                    if (k + 1 < K) kink = std::max(kink, kinks[at(i, j, k, ch)]);
                    // the slope from row to row (per image row), and B's kink at lattice row j
                    double g = 0.0, kappa = 0.0;
                    if (j > 0) g = std::max(g, rows[at(i, j - 1, k, ch)]);
                    if (j + 1 < nj) g = std::max(g, rows[at(i, j, k, ch)]);
                    if (j > 0 && j + 1 < nj)
                        for (const int q : {k, k + 1})
                            kappa = std::max(kappa, curves[at_q(i, j, q, ch)]);
                    const double c = lo > 0.0 ? (g * (stride - 1) + kink) / lo : inf;
                    const double lateral = lo > 0.0 ? kappa * stride / 4.0 / lo : inf;
                    C[k] = std::max(C[k], c);
                    T[k] = std::max(T[k], lateral);
                }
    // Every slab at or beyond a group's nearest depth: the largest coefficients from there on.
    for (int k = K - 1; k >= 0; --k) {
        reach[k] = l.z[k + 1] - l.z[k];
        if (k + 1 < K) {
            A[k] = std::max(A[k], A[k + 1]);
            C[k] = std::max(C[k], C[k + 1]);
            T[k] = std::max(T[k], T[k + 1]);
            reach[k] = std::min(reach[k], reach[k + 1]);
        }
    }
    BackscatterRowBounds b;
    b.stride = stride;
    b.z_max = float(l.z_max());
    b.bucket_scale = float(kBuckets / l.z_max());
    b.buckets.resize(kBuckets);
    for (int q = 0, k = 0; q < kBuckets; ++q) {
        const double zq = q / double(b.bucket_scale);
        while (k < K - 1 && l.z[k + 1] <= zq) ++k;
        BackscatterRowBounds::Coefficients& co = b.buckets[q];
        const bool finite = std::isfinite(A[k]) && std::isfinite(C[k]) && std::isfinite(T[k]);
        // (float coefficients rounded up, so that the float test is never looser)
        co.a = finite ? std::nextafter(float(A[k]), std::numeric_limits<float>::max()) : 0.0f;
        co.c = finite ? std::nextafter(float(C[k]), std::numeric_limits<float>::max()) : 0.0f;
        co.room = finite ? float(tol) * (1.0f - 1e-6f) : -1.0f;
        co.room_kinked = finite && tol > T[k] ? float(tol - T[k]) * (1.0f - 1e-6f) : -1.0f;
        co.reach = float(reach[k]);
    }
    return b;
}

DEEPSEA_CLONES
void lookup_depth_row(int n, const float* __restrict z, float z_max, float* __restrict out) {
#pragma omp simd
    for (int u = 0; u < n; ++u) out[u] = clamp_depth(z[u], z_max);
}

DEEPSEA_CLONES
int interpolate_backscatter_row(int n, float t, const float* __restrict z0,
                                const float* __restrict z1, const float* __restrict raw,
                                const float* __restrict b0, const float* __restrict b1,
                                const BackscatterRowBounds& b, bool kinked, float* __restrict out,
                                int* __restrict left) {
    const float z_max = b.z_max, scale = b.bucket_scale;
    // (locals: the stores to out could otherwise change b's vector, as far as GCC knows)
    const BackscatterRowBounds::Coefficients* __restrict buckets = b.buckets.data();
    const int last = int(b.buckets.size()) - 1;
    const Float8 zmax8 = Float8{} + z_max, t8 = Float8{} + t;
    const float far = float(kFarDepth);
    std::int32_t far_bits;
    std::memcpy(&far_bits, &far, sizeof far_bits);
    const auto lerp_pixel = [&](int u) {
        for (int ch = 0; ch < 3; ++ch) {
            const std::size_t i = 3 * std::size_t(u) + ch;
            out[i] = b0[i] + t * (b1[i] - b0[i]);
        }
    };
    int count = 0, u = 0;
    for (; u + 8 <= n; u += 8) {
        const Float8 za = load8(z0 + u), zb = load8(z1 + u);
        const Float8 zc = clamp_raw8(load8(raw + u), zmax8, far_bits);
        const Float8 d1 = abs8(za + t8 * (zb - za) - zc);
        const Float8 da = abs8(za - zc), db = abs8(zb - zc);
        const Float8 d2 = da < db ? db : da;
        // the nearest of the 24 depths: lane-wise, then across lanes by halves
        Float8 lo = za < zb ? za : zb;
        lo = zc < lo ? zc : lo;
        lo = min8(lo, __builtin_shufflevector(lo, lo, 4, 5, 6, 7, 0, 1, 2, 3));
        lo = min8(lo, __builtin_shufflevector(lo, lo, 2, 3, 0, 1, 6, 7, 4, 5));
        lo = min8(lo, __builtin_shufflevector(lo, lo, 1, 0, 3, 2, 5, 4, 7, 6));
        const BackscatterRowBounds::Coefficients& co = coefficients(buckets, last, scale, lo[0]);
        const float room = kinked ? co.room_kinked : co.room;
        const auto ok = (co.a * d1 + co.c * d2 <= room) & (d2 <= co.reach);
        std::uint64_t w[4];
        std::memcpy(w, &ok, sizeof w);
        if ((w[0] & w[1] & w[2] & w[3]) == ~std::uint64_t(0)) {
            // 24 interleaved values, three whole vectors
            for (int q = 0; q < 3; ++q) {
                const std::size_t i = 3 * std::size_t(u) + 8 * q;
                const Float8 x0 = load8(b0 + i), x1 = load8(b1 + i);
                const Float8 x = x0 + t8 * (x1 - x0);
                std::memcpy(out + i, &x, sizeof x);
            }
            continue;
        }
        for (int j = 0; j < 8; ++j) {
            if (ok[j]) {
                lerp_pixel(u + j);
            } else {
                left[count++] = u + j;
            }
        }
    }
    for (; u < n; ++u) {
        const float za = z0[u], zb = z1[u], zc = clamp_raw(raw[u], z_max, far_bits);
        const float d1 = std::fabs(za + t * (zb - za) - zc);
        const float d2 = std::max(std::fabs(za - zc), std::fabs(zb - zc));
        const BackscatterRowBounds::Coefficients& co =
            coefficients(buckets, last, scale, std::min(std::min(za, zb), zc));
        if (co.a * d1 + co.c * d2 <= (kinked ? co.room_kinked : co.room) && d2 <= co.reach) {
            lerp_pixel(u);
        } else {
            left[count++] = u;
        }
    }
    return count;
}

}  // namespace deepsea
