// The baker's orders >= 2 in front of an absorbing wall (MonteCarlo::wall) against the path
// tracer's water light with a real plane: two estimators written apart (docs/reference.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "deepsea/optics/multiple_scattering.h"
#include "deepsea/reference/path_tracer.h"
#include "reference_fixtures.h"

namespace deepsea {

namespace {

struct Sum {
    Rgb value, var;
};

/// Sum over the camera's pixels of the baker's orders >= 2 up to planar depth z, with or
/// without the wall there (the sample after z is far beyond, so z's is walled when asked).
Sum baker_sum(const Camera& cam, const Transport& tr, double z, bool wall, int paths) {
    Sum s;
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const Vec3 r = cam.ray(u, v);
            const std::vector<double> t{0.0, z * length(r), 30.0 * length(r)};
            const std::uint64_t stream = std::uint64_t(v * cam.width + u);
            const Estimate e =
                higher_orders_cumulative(tr, normalize(r), t, MonteCarlo{paths, 3, wall}, stream);
            s.value += e.value[1];
            s.var += e.std_error[1] * e.std_error[1];
        }
    }
    return s;
}

}  // namespace

TEST(Wall, OrdersTwoAndUpInFrontOfAnAbsorbingWallAreThePathTracersWaterLight) {
    // A plane 0.8 m away in water that scatters much of its light backward (albedo 0.9, HG
    // 0.3): the water beyond the plane would send back a large share of the orders >= 2.
    const Camera cam = testing::camera(4, 3);
    const Rig rig = testing::two_spots();
    const Water w = testing::hg_water(Rgb(0.5, 0.6, 0.7), Rgb(0.45, 0.54, 0.63), 0.3);
    const double z = 0.8;
    const testing::Scene scene = testing::plane(cam, z);
    PathTracerOptions opt;
    opt.paths = 8192;
    opt.min_order = 2;
    const PathTraced pt = render_path_traced(cam, rig, w, scene.rgb, scene.depth, opt);

    const Transport tr(rig, w);
    const Sum walled = baker_sum(cam, tr, z, true, 8192);
    const Sum open = baker_sum(cam, tr, z, false, 8192);
    for (int c = 0; c < 3; ++c) {
        const double ref = testing::bin_sum(pt.layers.backscatter, 0, 0, c, 4);
        const double ref_var = testing::bin_sum(pt.std_error.backscatter, 0, 0, c, 4, true);
        const double se = std::sqrt(ref_var + walled.var[c]);
        std::printf(
            "channel %d: path tracer %.5g, walled %.5g (%+.1f %%, %.1f SE), "
            "without walls %.5g (%+.1f %%)\n",
            c, ref, walled.value[c], 100.0 * (walled.value[c] / ref - 1.0),
            (walled.value[c] - ref) / se, open.value[c], 100.0 * (open.value[c] / ref - 1.0));
        EXPECT_LT(std::abs(walled.value[c] - ref), 4.0 * se + 0.01 * ref);
        // Can fail: water without walls keeps the light from beyond the plane.
        const double se_open = std::sqrt(ref_var + open.var[c]);
        EXPECT_GT(open.value[c] - ref, 4.0 * se_open);
    }
}

TEST(Wall, SameLightInOpenWaterAndNeverMoreInFrontOfAWall) {
    // The same paths: the last sample is water without walls either way, and every walled
    // sample holds at most what the wall-less one does (a path's light is only taken away).
    const Rig rig = testing::two_spots();
    const Water w = testing::hg_water(Rgb(0.8, 0.8, 0.8), Rgb(0.6, 0.6, 0.6), 0.85);
    const Transport tr(rig, w);
    const std::vector<double> t{0.0, 0.5, 1.0, 2.0, 4.0, 8.0};
    const Vec3 dir = normalize(Vec3(0.1, -0.05, 1.0));
    const Estimate a = higher_orders_cumulative(tr, dir, t, MonteCarlo{2000, 4, true}, 0);
    const Estimate b = higher_orders_cumulative(tr, dir, t, MonteCarlo{2000, 4, false}, 0);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(a.value.back()[c], b.value.back()[c]);
    for (std::size_t k = 1; k + 1 < t.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_LE(a.value[k][c], b.value[k][c]);
            EXPECT_GE(a.value[k][c], a.value[k - 1][c]);
        }
    }
    EXPECT_LT(a.value[3].r, 0.99 * b.value[3].r);  // a wall 2 m away takes something
}

}  // namespace deepsea
