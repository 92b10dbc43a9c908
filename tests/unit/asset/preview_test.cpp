// The preview grid's size (issue 29): bounded for every camera validate() accepts, however
// wide, with coarser voxels when the frustum is wide; every voxel's leaf node in the extent.
#include "preview.h"

#include <gtest/gtest.h>

#include <cmath>

#include "deepsea/optics/schema.h"
#include "test_assets.h"

namespace deepsea {
namespace {

/// The widest camera validate() accepts at this size: edge rays at the angle limit (a hair in).
Camera widest(int width, int height) {
    const double tan_max = std::tan(kMaxRayAngleDeg * M_PI / 180.0);
    const double fx = 0.5 * width / tan_max * (1.0 + 1e-6);
    const double fy = 0.5 * height / tan_max * (1.0 + 1e-6);
    return Camera{width, height, fx, fy, 0.5 * (width - 1), 0.5 * (height - 1)};
}

/// Backscatter that rises within `scale` metres of the camera: the preview depth is short and
/// the frustum there is wide in voxels of the pixel footprint.
Asset near_asset(const Camera& cam, double z_max, double scale) {
    return test::function_asset(cam, 8, DepthScheme::Log, 32, z_max,
                                [scale](double, double, double z) {
                                    return Rgb{1.0, 0.9, 0.8} * (1.0 - std::exp(-z / scale));
                                });
}

/// The documented bound (preview.h): at most max_depth slabs of at most about max_across^2
/// voxels when the voxel is fine, at most 8 slabs of at most
/// (W / p + 8 W / fx + 1) x (H / p + 8 H / fy + 1) when it is coarse.
double bound(const Camera& cam, int max_depth, int max_across) {
    const double p = std::max(1.0, double(std::max(cam.width, cam.height)) / max_across);
    const double fine = double(max_depth) * (cam.width / p + 2) * (cam.height / p + 2);
    const double coarse = 8.0 * (cam.width / p + 8 * cam.width / cam.fx + 2) *
                          (cam.height / p + 8 * cam.height / cam.fy + 2);
    return std::max(fine, coarse);
}

TEST(Preview, WidestAcceptedCamerasStayWithinTheBound) {
    for (const Camera& cam : {widest(320, 240), widest(64, 48), widest(800, 800)}) {
        ASSERT_NO_THROW(validate(cam));
        for (int across : {8, 32, 192}) {
            for (double scale : {0.05, 0.5, 5.0}) {
                SCOPED_TRACE(std::to_string(cam.width) + " px, across " + std::to_string(across) +
                             ", scale " + std::to_string(scale));
                const detail::Preview p =
                    detail::make_preview(near_asset(cam, 10.0, scale), 128, across);
                ASSERT_GT(p.voxels.size(), 0u);
                EXPECT_LE(double(p.voxels.size()), bound(cam, 128, across));
                EXPECT_LE(p.depth, 10.0 * (1 + 1e-9));
                EXPECT_GE(p.voxel_size, 1e-4);
                // Every voxel's leaf node lies within the depth extent [-z_max, 0].
                for (const detail::PreviewVoxel& v : p.voxels) {
                    ASSERT_LT(v.c, 0);
                    ASSERT_LE(8.0 * std::ceil(-v.c / 8.0) * p.voxel_size, 10.0 * (1 + 1e-9));
                }
            }
        }
    }
}

TEST(Preview, AWideFrustumKeepsTheFootprintVoxel) {
    // 320x240 at the angle limit (fx 28.2), 32 voxels across: the footprint of 10 pixels at
    // the preview depth is wider than depth / 8. Shrinking the voxel to depth / 8 (as before)
    // put 8 x 11.3 voxels across the far slab and 8 slabs; the footprint voxel covers the depth
    // in fewer slabs, with at most the pixels / 10 across (plus the rounding up of the depth).
    const Camera cam = widest(320, 240);
    const detail::Preview p = detail::make_preview(near_asset(cam, 10.0, 0.05), 128, 32);
    EXPECT_GT(p.voxel_size, p.depth / 8.0);
    const int slabs = int(std::lround(p.depth / p.voxel_size));
    EXPECT_LT(slabs, 8);
    EXPECT_LE(double(p.voxels.size()), double(slabs) * (32 + 12) * (24 + 10));
}

TEST(Preview, VoxelSizeCases) {
    const Camera narrow{800, 800, 600.0, 600.0, 399.5, 399.5};
    double depth = 5.0;
    // Fine: 128 deep, a whole number of leaves.
    double h = detail::preview_voxel_size(narrow, 10.0, 128, 192, depth);
    EXPECT_DOUBLE_EQ(depth, 5.0);
    EXPECT_NEAR(depth / h / 8.0, std::round(depth / h / 8.0), 1e-9);
    EXPECT_LE(depth / h, 128.0 + 1e-9);
    // Coarse: the footprint of 10 pixels at fx 28.2 (0.35 x depth): 3 voxels cover the depth.
    const Camera wide = widest(320, 240);
    depth = 0.5;
    h = detail::preview_voxel_size(wide, 10.0, 128, 32, depth);
    EXPECT_NEAR(h, 10.0 * 0.5 / std::min(wide.fx, wide.fy), 1e-12);
    EXPECT_NEAR(depth, 3 * h, 1e-12);
    // A footprint of 40 pixels (1.4 x depth): at most depth / 2, 2 deep.
    depth = 0.5;
    h = detail::preview_voxel_size(wide, 10.0, 128, 8, depth);
    EXPECT_DOUBLE_EQ(h, 0.25);
    EXPECT_DOUBLE_EQ(depth, 0.5);
    // Coarse, but 8 of them would reach beyond z_max = 1.5 m: depth / 8, 8 deep.
    depth = 0.5;
    h = detail::preview_voxel_size(wide, 1.5, 128, 8, depth);
    EXPECT_DOUBLE_EQ(h, 0.5 / 8);
    EXPECT_DOUBLE_EQ(depth, 0.5);
    // Never below 0.1 mm (OpenVDB's transforms stop near 14 micrometres).
    depth = 1e-6;
    h = detail::preview_voxel_size(narrow, 0.01, 128, 192, depth);
    EXPECT_GE(h, 1e-4);
    EXPECT_LE(8.0 * h, 0.01 * (1 + 1e-9));
}

}  // namespace
}  // namespace deepsea
