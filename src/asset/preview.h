#pragma once
// The `density` / `color` preview: the asset's in-scatter resampled onto a world-space linear
// grid (docs/asset-format.md). Pure arithmetic on the flat arrays, kept out of asset_write.cpp
// so that only the file's two translation units compile OpenVDB.

#include <vector>

#include "deepsea/asset/asset.h"

namespace deepsea::detail {

/// One preview voxel at world index (a, b, c); world position = voxel_size * (a, b, c) in the
/// file's world frame (camera_to_world).
struct PreviewVoxel {
    int a, b, c;
    float density;   ///< in-scatter luminance / density_scale, 1 at the brightest voxel
    float color[3];  ///< chromaticity: RGB / max(R, G, B)
};

struct Preview {
    double voxel_size = 0.0;           ///< metres
    double density_scale = 0.0;        ///< in-scatter luminance (radiance per metre) at density 1
    double depth = 0.0;                ///< planar depth the preview covers, metres
    long trimmed = 0;                  ///< voxels left out to keep the leaf nodes in the extent
    std::vector<PreviewVoxel> voxels;  ///< in a fixed order (deterministic files)
};

/// The preview's voxel size for a preview `depth` (metres) in a lattice of depth z_max: the
/// footprint of p = max(1, longer side / max_across) pixels at that depth, but at least
/// depth / max_depth and 0.1 mm; then, if that is at most depth / 8, shrunk so that depth is a
/// whole number of 8-voxel leaf nodes. A coarser voxel (a wide field of view) is kept, but at
/// most depth / 2, and the depth becomes the fewest such voxels that cover it (2 to 8), unless
/// their leaf node would reach beyond z_max: then the voxel is depth / 8. So there are at most
/// about min(pixels, max_across^2) x max_depth / 3 voxels when the voxel is fine, and at most 8
/// slabs of (W / p + 8 W / fx + 1) x (H / p + 8 H / fy + 1) when it is coarse: the field of
/// view enters only through W / fx and H / fy, which validate(Camera) bounds (2 tan 80 degrees
/// = 11.3). Updates `depth` to what the preview covers.
double preview_voxel_size(const Camera& camera, double z_max, int max_depth, int max_across,
                          double& depth);

/// Builds the preview: voxels where density >= 1e-3, up to the depth beyond which every
/// lattice cell's in-scatter is below 1 % of the brightest, inside the image's frustum, with
/// cubic voxels of preview_voxel_size. Every voxel's leaf node lies in frustum_extent.
Preview make_preview(const Asset& asset, int max_depth, int max_across);

}  // namespace deepsea::detail
