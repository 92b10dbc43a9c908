#pragma once
// Internal to the runtime: each pixel's depth slab in a baked lattice and its weight within it
// (asset_backscatter.cpp's lookup, its first step).

#include <vector>

namespace deepsea {

/// A lattice's depth samples z_0 = 0 < ... < z_K = z_max as the lookup reads them: uniform
/// buckets over [0, z_max], no wider than the thinnest slab, each holding the slab its start
/// falls in, so that a depth's slab is its bucket's or the next. The buckets of one slab are a
/// run (first, last), as the samples increase.
struct DepthSlabs {
    explicit DepthSlabs(const std::vector<double>& z);

    std::vector<float> z, inv_h;  ///< samples and 1 / slab thickness
    std::vector<float> znext;     ///< z[k + 1], and for the last slab the largest float
    std::vector<int> bucket;
    std::vector<int> first, last;  ///< per slab: its run of buckets (first > last: none)
    float bucket_scale = 0.0f;     ///< buckets per metre
};

/// Slab k_u and weight wz_u of n depths (open water z == 0, never NaN or inf). z == 0 and any
/// depth beyond z_max look z_max up:
///   z'_u = min(z_u, z_max),  k_u = bucket's slab, or the next where z_(k + 1) <= z'_u,
///   wz_u = clamp((z'_u - z_(k_u)) / (z_(k_u + 1) - z_(k_u)), 0, 1).
/// Eight pixels at a time: where their buckets all lie in one slab's run, that slab's values
/// are read once for all eight (no gather); other groups go pixel by pixel. The same values as
/// depth_cells_each, bit for bit.
void depth_cells(int n, const float* z, const DepthSlabs& s, int* k, float* wz);

/// The same, pixel by pixel (the definition the grouped form is tested against).
void depth_cells_each(int n, const float* z, const DepthSlabs& s, int* k, float* wz);

}  // namespace deepsea
