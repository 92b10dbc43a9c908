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
    std::vector<PreviewVoxel> voxels;  ///< in a fixed order (deterministic files)
};

/// Builds the preview: voxels where density >= 1e-3, up to the depth beyond which every
/// lattice cell's in-scatter is below 1 % of the brightest, `resolution` voxels along it.
Preview make_preview(const Asset& asset, int resolution);

}  // namespace deepsea::detail
