#pragma once
/// \file The frustum lattice of a baked asset (docs/asset-format.md):
/// columns (i, j) at pixel positions (i * step, j * step) and depth samples
/// z_0 = 0 < z_1 < ... < z_K = z_max (planar z-depth, metres) shared by all columns.

#include <string>
#include <vector>

#include "deepsea/optics/camera.h"

namespace deepsea {

/// How the depth samples are spread over [0, z_max]. docs/asset-format.md has the formulas
/// and the measurements that chose the default.
enum class DepthScheme {
    Uniform,  ///< z_k = z_max k / K
    Taylor,   ///< the paper's Eq. 7: slab n has thickness proportional to K^n / n!
    Sqrt,     ///< uniform in sqrt(z): z_k = z_max (k / K)^2
    Log,      ///< uniform in log(z + z0): z_k = z0 ((1 + z_max / z0)^(k / K) - 1)
};

/// Name as written on the command line and in the asset's metadata: "uniform", "taylor", ...
const char* to_string(DepthScheme scheme);
/// Inverse of to_string; throws ConfigError listing the known names.
DepthScheme parse_depth_scheme(const std::string& name);

/// Default z0 of the Log scheme, metres: the depth scale below which the lamps' cones have
/// not yet filled the view of a rig with a ~1 m baseline (see docs/asset-format.md).
inline constexpr double kDefaultLogZ0 = 0.5;

/// The K + 1 depth samples of a scheme, ascending, z[0] = 0 and z[K] = z_max exactly.
/// K >= 1, z_max > 0, z0 > 0 (Log only); throws ConfigError otherwise.
std::vector<double> depth_samples(DepthScheme scheme, int K, double z_max,
                                  double z0 = kDefaultLogZ0);

/// Columns needed to cover `pixels` pixel centres 0 .. pixels-1 with a step of `step` pixels:
/// ceil((pixels - 1) / step) + 1 (the last column may lie up to step - 1 pixels beyond).
int lattice_count(int pixels, int step);

/// Two neighbouring lattice nodes i0, i1 and the weight w in [0, 1] of i1: the one
/// interpolation rule of every lookup in an asset (Asset::sample in double, the runtime's
/// per-frame tables in float).
template <class T>
struct LatticeCell {
    int i0 = 0, i1 = 0;
    T w = T(0);
};

/// The cell of coordinate x (lattice units: pixel / step) among n >= 1 nodes, clamped to the
/// lattice: x <= 0 and NaN give the first node, x >= n - 1 the last (w = 1 between the last
/// two; a single node has i1 = i0 and w = 0).
template <class T>
inline LatticeCell<T> lattice_cell(T x, int n) {
    if (!(x > T(0))) x = T(0);  // also NaN
    const T last = T(n - 1);
    if (x >= last) return {n > 1 ? n - 2 : 0, n - 1, n > 1 ? T(1) : T(0)};
    const int i0 = int(x);
    return {i0, i0 + 1, x - T(i0)};
}

/// a + w (b - a): linear interpolation, w = 0 gives a, w = 1 gives b.
template <class T>
inline T lerp(T a, T b, T w) {
    return a + w * (b - a);
}

/// A position between two depth samples: z = z[k] + w (z[k + 1] - z[k]), 0 <= w <= 1.
struct DepthPosition {
    int k = 0;
    double w = 0.0;
};

/// The sampling lattice. Column (i, j) is the ray of pixel (i * step, j * step); sample k of
/// that column is the point at planar depth z[k] on the ray.
struct Lattice {
    int step = 0;  ///< pixels between columns (and rows), >= 1
    int ni = 0;    ///< columns, i = 0 .. ni - 1
    int nj = 0;    ///< rows, j = 0 .. nj - 1
    DepthScheme scheme = DepthScheme::Uniform;
    double z0 = kDefaultLogZ0;  ///< Log scheme's depth scale, metres (else unused)
    std::vector<double> z;      ///< K + 1 planar depths, metres, z[0] = 0

    /// K + 1, the number of samples per column.
    int nk() const { return int(z.size()); }
    /// K, the number of slabs.
    int slabs() const { return int(z.size()) - 1; }
    double z_max() const { return z.empty() ? 0.0 : z.back(); }
    long columns() const { return long(ni) * nj; }
    /// Pixel coordinates of column i and row j.
    double u(int i) const { return double(i) * step; }
    double v(int j) const { return double(j) * step; }

    /// Where planar depth z falls between samples, clamped to [0, z_max]: z <= 0 gives (0, 0),
    /// z >= z_max (also +inf and NaN, open water) gives (K - 1, 1). O(1) for every scheme but
    /// Taylor (binary search).
    DepthPosition depth_position(double z) const;

    bool operator==(const Lattice& o) const;
};

/// Largest lattice deepsea bakes or loads: columns x rows x depth samples (each point holds
/// RGB, so 50 million points are 0.6 GB of floats).
inline constexpr long long kMaxLatticePoints = 50'000'000;

/// ConfigError unless ni x nj x nk points are within kMaxLatticePoints (checked before any
/// allocation or work, by make_lattice and by the baker before its z_max search).
void check_lattice_size(long long ni, long long nj, long long nk);

/// The lattice of `camera` for a given step and depth samples (throws ConfigError for
/// step < 1, fewer than 2 samples, samples that do not start at 0 and ascend, or a lattice
/// larger than kMaxLatticePoints).
Lattice make_lattice(const Camera& camera, int step, DepthScheme scheme,
                     std::vector<double> z_samples, double z0 = kDefaultLogZ0);

}  // namespace deepsea
