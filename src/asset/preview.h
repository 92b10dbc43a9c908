#pragma once
// The `density` / `color` preview: the asset's in-scatter resampled onto a world-space linear
// grid (docs/asset-format.md). Pure arithmetic on the flat arrays, kept out of asset_file.cpp
// so that only one translation unit compiles OpenVDB.

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

/// The preview's voxel size for a preview `depth` (metres): the footprint of
/// max(1, longer side / max_across) pixels at that depth, but at least depth / max_depth;
/// then grown so that depth is a whole number of 8-voxel leaf nodes (at least one). So there
/// are at most about min(pixels, max_across^2) x max_depth / 3 voxels, whatever the field of
/// view.
double preview_voxel_size(const Camera& camera, double depth, int max_depth, int max_across);

/// Builds the preview: voxels where density >= 1e-3, up to the depth beyond which every
/// lattice cell's in-scatter is below 1 % of the brightest, inside the image's frustum, with
/// cubic voxels of preview_voxel_size. Every voxel's leaf node lies in frustum_extent.
Preview make_preview(const Asset& asset, int max_depth, int max_across);

}  // namespace deepsea::detail
