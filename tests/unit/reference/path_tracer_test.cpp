#include "deepsea/reference/path_tracer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/reference/reference.h"
#include "reference_fixtures.h"

namespace deepsea {

namespace {

using testing::bin_sum;

/// Order 1 against the exact single-scattering reference: every 4x4 bin of the water light
/// within 4 standard errors, the surface light exactly (a camera ray meets the pixel's own
/// point, whose lamp light has no randomness left).
void expect_single_scattering(const Water& water, const testing::Scene& scene, double z_open) {
    const Camera cam = testing::camera(32, 24);
    const Rig rig = testing::two_spots();
    ReferenceOptions ro;
    ro.open_water_z = z_open;
    ro.quadrature.rel_tol = 1e-7;
    const Layers ref = render_reference(cam, rig, water, scene.rgb, scene.depth, ro);
    PathTracerOptions opt;
    opt.paths = 256;
    opt.max_order = 1;
    opt.open_water_z = z_open;
    const PathTraced pt = render_path_traced(cam, rig, water, scene.rgb, scene.depth, opt);
    double worst = 0.0;
    for (int j = 0; j < cam.height / 4; ++j) {
        for (int i = 0; i < cam.width / 4; ++i) {
            for (int ch = 0; ch < 3; ++ch) {
                const double want = bin_sum(ref.backscatter, i, j, ch, 4);
                const double got = bin_sum(pt.layers.backscatter, i, j, ch, 4);
                const double se = std::sqrt(bin_sum(pt.std_error.backscatter, i, j, ch, 4, true));
                ASSERT_GT(se, 0.0);
                worst = std::max(worst, std::fabs(got - want) / se);
                EXPECT_LE(std::fabs(got - want), 4.0 * se)
                    << "bin (" << i << ", " << j << ") ch " << ch << ": " << got << " vs " << want;
                const double d = bin_sum(ref.direct, i, j, ch, 4);
                EXPECT_NEAR(bin_sum(pt.layers.direct, i, j, ch, 4), d, 1e-6 * d + 1e-12);
                EXPECT_EQ(bin_sum(pt.layers.forward, i, j, ch, 4), 0.0);
            }
        }
    }
    std::printf("worst 4x4 bin of the water light: %.2f SE\n", worst);
}

TEST(PathTracer, OrderOneIsSingleScatteringWithAPlane) {
    // Turbid, forward-peaked: c about 1, b about 0.8, HG 0.85; a tilted plane 2 m away.
    const Camera cam = testing::camera(32, 24);
    const Water w = testing::hg_water({1.0, 0.9, 0.95}, {0.8, 0.75, 0.8}, 0.85);
    expect_single_scattering(w, testing::plane(cam, 2.0, 0.15, -0.3), 0.0);
}

TEST(PathTracer, OrderOneIsSingleScatteringInOpenWater) {
    // A tabulated phase function, and open water that ends at z = 12 m.
    const Camera cam = testing::camera(32, 24);
    Water w = testing::hg_water({0.49, 0.2, 0.18}, {0.11, 0.12, 0.14}, 0.0);
    w.phase.kind = PhaseKind::PetzoldCoastal;
    expect_single_scattering(w, testing::plane(cam, 0.0), 12.0);
}

/// A small render of the turbid plane scene, all orders unless max_order says otherwise.
PathTraced small_render(long paths, std::uint64_t seed, int threads, int max_order = 0) {
    const Camera cam = testing::camera(8, 6);
    const testing::Scene s = testing::plane(cam, 2.0, 0.1, 0.0);
    const Water w = testing::hg_water({1.0, 0.9, 0.95}, {0.8, 0.75, 0.8}, 0.85);
    PathTracerOptions opt;
    opt.paths = paths;
    opt.seed = seed;
    if (max_order > 0) opt.max_order = max_order;
    return render_path_traced(cam, testing::two_spots(), w, s.rgb, s.depth, opt, {threads});
}

TEST(PathTracer, DeterministicPerSeedAtAnyThreadCount) {
    const PathTraced a = small_render(16, 7, 1), b = small_render(16, 7, 2);
    const PathTraced c = small_render(16, 8, 2);
    EXPECT_EQ(a.layers.final.data, b.layers.final.data);
    EXPECT_EQ(a.layers.forward.data, b.layers.forward.data);
    EXPECT_EQ(a.std_error.final.data, b.std_error.final.data);
    EXPECT_NE(a.layers.final.data, c.layers.final.data);
}

/// Image sum of one channel of a layer, and its standard error (independent pixels).
std::pair<double, double> image_sum(const Image& img, const Image& se, int ch) {
    double sum = 0.0, var = 0.0;
    for (int v = 0; v < img.height; ++v) {
        for (int u = 0; u < img.width; ++u) {
            sum += img.at(u, v, ch);
            var += std::pow(se.at(u, v, ch), 2);
        }
    }
    return {sum, std::sqrt(var)};
}

/// The median over pixels of b's standard error over a's, channel ch: robust to the few pixels
/// whose error estimate a heavy-tailed sample has thrown far off.
double median_error_ratio(const Image& se_a, const Image& se_b, int ch) {
    std::vector<double> r;
    for (int v = 0; v < se_a.height; ++v)
        for (int u = 0; u < se_a.width; ++u)
            if (se_a.at(u, v, ch) > 0.0) r.push_back(se_b.at(u, v, ch) / se_a.at(u, v, ch));
    std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
    return r[r.size() / 2];
}

TEST(PathTracer, StandardErrorShrinksAsOneOverSquareRootOfPaths) {
    // Single scattering: a bounded estimator, so four times the paths halve every error.
    {
        const PathTraced a = small_render(256, 3, 0, 1), b = small_render(1024, 4, 0, 1);
        for (int ch = 0; ch < 3; ++ch) {
            const auto sa = image_sum(a.layers.backscatter, a.std_error.backscatter, ch);
            const auto sb = image_sum(b.layers.backscatter, b.std_error.backscatter, ch);
            EXPECT_NEAR(sb.second / sa.second, 0.5, 0.05) << "channel " << ch;
            EXPECT_LE(std::fabs(sa.first - sb.first), 4.0 * std::hypot(sa.second, sb.second));
        }
    }
    // All orders, in clear water (HG 0.9, a plane at 3 m): the errors halve as well. Paths that
    // pass close to a lamp make the water's and the surface layers' errors (and their own
    // estimates) heavy-tailed at a few hundred paths (docs/reference.md): a few pixels' error
    // estimates can be far off (which ones differs with the compiler's floating point), so the
    // errors are compared pixel by pixel, by the median ratio; the two runs agree within their
    // errors.
    const Camera cam = testing::camera(8, 6);
    const testing::Scene scene = testing::plane(cam, 3.0, 0.1, 0.0);
    const Water clear = testing::hg_water({0.49, 0.2, 0.18}, {0.11, 0.12, 0.14}, 0.9);
    PathTracerOptions opt;
    opt.paths = 256;
    const PathTraced a =
        render_path_traced(cam, testing::two_spots(), clear, scene.rgb, scene.depth, opt);
    opt.paths = 1024;
    opt.seed = 2;
    const PathTraced b =
        render_path_traced(cam, testing::two_spots(), clear, scene.rgb, scene.depth, opt);
    for (int ch = 0; ch < 3; ++ch) {
        const double water =
            median_error_ratio(a.std_error.backscatter, b.std_error.backscatter, ch);
        EXPECT_GT(water, 0.3) << "channel " << ch;
        EXPECT_LT(water, 0.8) << "channel " << ch;
        const auto sa = image_sum(a.layers.final, a.std_error.final, ch);
        const auto sb = image_sum(b.layers.final, b.std_error.final, ch);
        std::printf(
            "channel %d: final %.5g +- %.2g %% (256 paths), %.5g +- %.2g %% (1024); per pixel, "
            "errors x %.2f\n",
            ch, sa.first, 100.0 * sa.second / sa.first, sb.first, 100.0 * sb.second / sb.first,
            median_error_ratio(a.std_error.final, b.std_error.final, ch));
        // 0.5 for a bounded estimator; 256 paths miss some of the tail, so a little above.
        const double shrink = median_error_ratio(a.std_error.final, b.std_error.final, ch);
        EXPECT_GT(shrink, 0.3) << "channel " << ch;
        EXPECT_LT(shrink, 0.8) << "channel " << ch;
        EXPECT_LE(std::fabs(sa.first - sb.first), 4.0 * std::hypot(sa.second, sb.second));
    }
}

TEST(PathTracer, OnlyOrderOneWhereTheWaterDoesNotScatter) {
    // b = 0: the plane cannot see itself, so every order above 1 is zero.
    const Camera cam = testing::camera(8, 6);
    const testing::Scene s = testing::plane(cam, 2.0, 0.2, 0.1);
    const Water w = testing::hg_water({0.3, 0.2, 0.1}, {0.0, 0.0, 0.0}, 0.0);
    PathTracerOptions opt;
    opt.paths = 64;
    const PathTraced pt = render_path_traced(cam, testing::two_spots(), w, s.rgb, s.depth, opt);
    const Layers ref = render_reference(cam, testing::two_spots(), w, s.rgb, s.depth);
    for (std::size_t i = 0; i < ref.direct.data.size(); ++i) {
        EXPECT_NEAR(pt.layers.direct.data[i], ref.direct.data[i], 1e-6 * ref.direct.data[i]);
        EXPECT_EQ(pt.layers.forward.data[i], 0.0f);
        EXPECT_EQ(pt.layers.backscatter.data[i], 0.0f);
        EXPECT_LE(pt.std_error.direct.data[i], 1e-6 * ref.direct.data[i]);
    }
    EXPECT_EQ(pt.layers.depth.data, ref.depth.data);
    EXPECT_EQ(pt.layers.transmission.data, ref.transmission.data);
}

TEST(PathTracer, RefusesWhatItCannotTrace) {
    const Camera cam = testing::camera(8, 6);
    testing::Scene s = testing::plane(cam, 2.0);
    const Water w = testing::hg_water({0.3, 0.2, 0.1}, {0.1, 0.1, 0.1}, 0.9);
    const Rig rig = testing::two_spots();
    PathTracerOptions opt;
    opt.paths = 1L << 40;
    EXPECT_THROW(render_path_traced(cam, rig, w, s.rgb, s.depth, opt), ConfigError);
    opt.paths = 4;
    opt.min_order = 3;
    opt.max_order = 2;
    EXPECT_THROW(render_path_traced(cam, rig, w, s.rgb, s.depth, opt), ConfigError);
    opt.min_order = 1;
    s.depth.at(3, 3) *= 0.9f;  // a bump: not one plane
    try {
        render_path_traced(cam, rig, w, s.rgb, s.depth, opt);
        ADD_FAILURE() << "a bump was taken for a plane";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("pixel (3, 3) lies"), std::string::npos) << e.what();
    }
}

}  // namespace

}  // namespace deepsea
