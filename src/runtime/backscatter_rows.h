#pragma once
// Internal to the runtime: the backscatter of rows between looked-up rows, the compositor's
// bounded approximation for the image alone (docs/runtime.md, "Bounded approximations").

#include <vector>

#include "deepsea/asset/lattice.h"

namespace deepsea {

/// Rows between looked-up rows in the compositor's image alone (AssetBackscatter's bounds):
/// the largest power of two up to one per 75 px of focal length, 2 to 16 (8 at the demo's
/// fy = 600), so that the rows are as far apart in angle at every resolution: the bound's
/// depth differences between them grow with the angle.
inline int backscatter_row_stride(double fy) {
    int r = 2;
    while (r < 16 && 2 * r * 75.0 <= fy) r *= 2;
    return r;
}

/// When a pixel's B may be taken as the linear interpolation of the B of the pixels above and
/// below it in two looked-up rows (`stride` rows apart), so that the error is at most `tol` of
/// the pixel's own B, per channel. With t the pixel's row weight, z its depth and z0, z1 the
/// two others' (each min(z, z_max), open water z_max), the lattice's piecewise-linear B bounds
/// the error relative to B by
///   a |(z0 + t (z1 - z0)) - z| + c max(|z0 - z|, |z1 - z|) + lateral,
/// a: the steepest slab slope over its smaller end (the linear part), c: slope changes at a
/// slab boundary and between lattice rows over the rows' distance (the curvature), lateral:
/// B's kink at fixed depth where a lattice row lies between the two rows (stride / 4 of the
/// change of its slope; 0 where none does: B is linear in v between lattice rows). Where
/// max |z_i - z| exceeds the thinnest slab (more than one boundary) or the bound exceeds tol,
/// the pixel is looked up. The coefficients are the largest over the lattice's columns and
/// channels and over every slab at or beyond the one of the three depths' nearest, per bucket
/// of that depth.
struct BackscatterRowBounds {
    struct Coefficients {
        float a = 0.0f, c = 0.0f;
        float room = -1.0f;         ///< tol (< 0: never)
        float room_kinked = -1.0f;  ///< tol less the lateral term (< 0: never)
        float reach = 0.0f;         ///< the thinnest slab at or beyond the bucket's
    };
    int stride = 1;             ///< rows between looked-up rows
    float z_max = 0.0f;         ///< the lattice's last depth
    float bucket_scale = 0.0f;  ///< buckets per metre
    std::vector<Coefficients> buckets;
    /// Per pair of looked-up rows (v0 / stride): whether a lattice row lies between them.
    std::vector<unsigned char> kinked;
};

/// The bounds of a lattice's values (Asset::values' layout) for frames with `rows_per_step`
/// image rows between lattice rows.
BackscatterRowBounds backscatter_row_bounds(const Lattice& l, const float* values,
                                            double rows_per_step, int stride, double tol);

/// A looked-up row's planar depths (sanitised: open water 0) as interpolate_backscatter_row
/// takes them: each as the lookup reads it, min(z, z_max), open water z_max.
void lookup_depth_row(int n, const float* z, float z_max, float* out);

/// B of n pixels of a row between two looked-up rows (b0 at t = 0, b1 at t = 1; interleaved
/// RGB, `kinked` as the pair's flag) from the two rows' depths as lookup_depth_row gives them
/// (z0, z1) and the row's own raw planar depths (`raw`: any float, open water where optics'
/// has_surface says so, tested here on the float's bits):
///   out = b0 + t (b1 - b0)
/// where the bounds allow it. Returns how many pixels they do not, their columns in `left` in
/// increasing order (their out is not written): the caller looks those up.
int interpolate_backscatter_row(int n, float t, const float* z0, const float* z1, const float* raw,
                                const float* b0, const float* b1, const BackscatterRowBounds& b,
                                bool kinked, float* out, int* left);

}  // namespace deepsea
