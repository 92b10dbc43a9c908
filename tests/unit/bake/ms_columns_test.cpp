// Multiple scattering's columns: the angular rule (lattice_rule.h, auto_ms_stride) and the
// bake's check of orders >= 2 (higher_orders_check.h) on crossing pencil beams.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "../asset/test_assets.h"
#include "deepsea/bake/bake.h"
#include "deepsea/bake/higher_orders.h"
#include "deepsea/bake/higher_orders_check.h"
#include "deepsea/bake/lattice_rule.h"
#include "deepsea/optics/multiple_scattering.h"

namespace deepsea {
namespace {

/// 90 degrees across: fx = width / 2.
Camera wide(int width, int height) {
    return {width, height, 0.5 * width, 0.5 * width, 0.5 * (width - 1), 0.5 * (height - 1)};
}

/// Two Gaussian beams 0.5 m either side of the camera, crossing on the axis at 2 m.
Rig pencils(double sigma_deg) { return test::mirrored_lamps("pencils", 0.25, 1.0, sigma_deg); }

TEST(MsColumns, SpacingFollowsTheNarrowestDetailInAngleNotPixels) {
    const Water w = test::test_water();
    const double narrow = ms_detail(wide(64, 48), pencils(8.0), w);
    const double broad = ms_detail(wide(64, 48), pencils(35.0), w);
    EXPECT_LT(narrow, broad);
    // The phase function widens it: never below its median angle, nor below the beam's width.
    Water iso = w;
    iso.phase.kind = PhaseKind::Isotropic;
    EXPECT_GT(ms_detail(wide(64, 48), pencils(8.0), iso), narrow);
    EXPECT_GE(narrow, 8.0 * M_PI / 180.0 * 0.5);
    // The same field of view at twice the pixels: the same angle, twice the pixels per stride.
    const int s1 = auto_ms_stride(wide(200, 150), pencils(8.0), w, 1, 64);
    const int s2 = auto_ms_stride(wide(400, 300), pencils(8.0), w, 1, 64);
    EXPECT_NEAR(double(s2) / s1, 2.0, 2.0 / s1);
    EXPECT_LE(s1 * (1.0 / 100.0), kMaxMsSpacing);  // radians per pixel: 1 / fx
    // Wide beams in wide water: the ceiling.
    const Camera demo{800, 800, 600.0, 600.0, 400.0, 400.0};
    EXPECT_EQ(auto_ms_stride(demo, test::two_lamp_rig(), iso, 16, 65536),
              int(std::floor(kMaxMsSpacing * 600.0 / 16)));
}

TEST(MsColumns, StaysWithinThePathBudget) {
    const Camera big{4000, 3000, 500.0, 500.0, 1999.5, 1499.5};
    const int paths = 65536;
    const int stride = auto_ms_stride(big, pencils(2.0), test::test_water(), 1, paths);
    const long columns =
        higher_order_columns(lattice_count(4000, 1), lattice_count(3000, 1), stride);
    EXPECT_LE(double(columns) * paths, kMsPathBudget);
    EXPECT_GT(double(higher_order_columns(4000, 3000, stride - 1)) * paths, kMsPathBudget);
}

TEST(MsColumns, InterpolationIsBilinearBetweenComputedColumns) {
    MsColumns ms;
    ms.ci = computed_indices(9, 4);  // 0 4 8
    ms.cj = computed_indices(6, 4);  // 0 4 5
    ASSERT_EQ(ms.cj.back(), 5);
    ms.nk = 1;
    for (int a : ms.ci)
        for (int b : ms.cj) ms.values.push_back(Rgb{1.0 + a, 2.0 * b, double(a * b)});
    // A bilinear function is reproduced exactly, anywhere in between.
    for (double x : {0.0, 1.5, 4.0, 6.25, 8.0})
        for (double y : {0.0, 2.5, 4.5, 5.0}) {
            const Rgb v = ms.at(x, y, 0);
            EXPECT_NEAR(v.r, 1.0 + x, 1e-12);
            EXPECT_NEAR(v.g, 2.0 * y, 1e-12);
            EXPECT_NEAR(v.b, x * y, 1e-12);
        }
}

TEST(MsColumns, LogInterpolationFollowsExponentialFalloff) {
    MsColumns ms;
    ms.ci = computed_indices(7, 3);  // 0 3 6
    ms.cj = computed_indices(7, 3);
    ms.nk = 1;
    // Light falling off exponentially away from a beam (red, green); blue 0 at one column.
    const auto f = [](double x, double y) {
        return Rgb{std::exp(-0.8 * x - 0.3 * y), 2.0 * std::exp(-0.5 * y), x * y};
    };
    for (int a : ms.ci)
        for (int b : ms.cj) ms.values.push_back(f(a, b));
    ms.log = true;
    for (double x : {0.0, 1.0, 1.5, 4.0, 6.0})
        for (double y : {0.0, 2.0, 4.5}) {
            const Rgb v = ms.at(x, y, 0), want = f(x, y);
            EXPECT_NEAR(v.r, want.r, 1e-12 * want.r);
            EXPECT_NEAR(v.g, want.g, 1e-12 * want.g);
            // Blue: the cells touching x = 0 or y = 0 hold a 0, so bilinear (exact for x y);
            // the others are positive and log-bilinear (not exact for x y, within 25 %).
            if (x < 3.0 || y < 3.0)
                EXPECT_NEAR(v.b, want.b, 1e-12);
            else
                EXPECT_NEAR(v.b, want.b, 0.25 * want.b);
        }
    // Plain bilinear lifts such light between columns (a chord above a convex curve).
    ms.log = false;
    EXPECT_GT(ms.at(1.5, 0.0, 0).r, 1.1 * f(1.5, 0.0).r);
}

/// The pencil rig on a 12x9, 90 degree camera (9.5 degree pixels), test_water (c 0.19 1/m in
/// green, b 0.12, HG 0.9), 1024 paths per column: this stride (0: the angular rule).
BakeSettings pencil_settings(Scattering scattering, int stride) {
    BakeSettings s;
    s.step = 1;
    s.depth_samples = 8;
    s.scheme = DepthScheme::Uniform;
    s.z_max = 4.0;
    s.scattering = scattering;
    s.higher_orders.paths = 1024;
    s.higher_orders.lamp_samples = 8;
    s.higher_orders.stride = stride;
    return s;
}

TEST(MsColumns, PencilBeamsAreResolvedBetweenColumns) {
    const Camera cam = wide(12, 9);
    const Rig rig = pencils(8.0);
    const Water water = test::test_water();
    const Asset single = bake(cam, rig, water, pencil_settings(Scattering::Single, 0));
    const Asset rule = bake(cam, rig, water, pencil_settings(Scattering::Multiple, 0));
    const Asset old = bake(cam, rig, water, pencil_settings(Scattering::Multiple, 64));
    ASSERT_EQ(old.info.higher_orders.stride, 64);  // 64 px on a 1 px lattice: the corners only
    ASSERT_LT(rule.info.higher_orders.stride, 4);

    // The beams cross on the axis at 2 m: look there, midway between two lattice columns, and
    // estimate orders >= 2 directly along that pixel's own ray with 8x the paths.
    // The beams as this camera sees them (u 0.5 .. 2.5 and 8.5 .. 10.5, on the middle rows),
    // midway between lattice columns: orders >= 2 estimated directly along each pixel's own
    // ray with 8x the paths.
    const Transport transport(rig, water);
    const double z = 4.0;
    for (const auto& [u, v] : {std::pair{0.5, 4.0}, std::pair{8.5, 4.0}, std::pair{2.5, 2.5}}) {
        const std::vector<double> t{0.0, z * length(cam.ray(u, v))};
        const Estimate direct =
            higher_orders_cumulative(transport, normalize(cam.ray(u, v)), t, {8192, 99}, 7);
        for (int c = 0; c < 3; ++c) {
            const double truth = direct.value[1][c], one = single.sample(u, v, z)[c];
            // Standard error of the difference: the direct estimate's and two bracketing
            // columns' of 8x fewer paths (sqrt(8 / 2) = 2 times the direct one's each).
            const double se = std::sqrt(5.0) * direct.std_error[1][c];
            const double with_rule = rule.sample(u, v, z)[c] - one;
            const double with_old = old.sample(u, v, z)[c] - one;
            SCOPED_TRACE("pixel (" + std::to_string(u) + ", " + std::to_string(v) + "), channel " +
                         std::to_string(c));
            EXPECT_LT(std::abs(with_rule - truth), 4.0 * se);
            EXPECT_LT(std::abs(with_rule - truth) / (one + truth), 0.10);
            // Can fail: the old spacing misses the beams' light (5-20x too little here).
            EXPECT_GT(truth - with_old, 4.0 * se);
            EXPECT_GT((truth - with_old) / (one + truth), 0.10);
        }
    }

    // The bake's own check ran, on columns it did not compute, and says the rule is better.
    const HigherOrderCheck& f = rule.info.higher_orders.check;
    const HigherOrderCheck& o = old.info.higher_orders.check;
    ASSERT_TRUE(f.done && o.done);
    EXPECT_GE(f.columns, 24);
    EXPECT_EQ(f.paths, 2 * 1024);
    EXPECT_GE(f.max_rel, f.mean_rel);
    EXPECT_GT(f.rel_std_error, 0.0);
    EXPECT_LT(f.mean_rel, o.mean_rel);
}

TEST(MsColumns, CheckPixelsLieBetweenComputedColumns) {
    Asset a;
    a.info.camera = wide(40, 30);
    a.info.rig = pencils(8.0);
    a.info.lattice = make_lattice(a.info.camera, 2, DepthScheme::Uniform,
                                  depth_samples(DepthScheme::Uniform, 4, 4.0, 1.0), 1.0);
    MsColumns ms;
    ms.ci = computed_indices(a.info.lattice.ni, 3);
    ms.cj = computed_indices(a.info.lattice.nj, 3);
    const auto pixels = ms_check_pixels(a, ms);
    ASSERT_FALSE(pixels.empty());
    for (const auto& [u, v] : pixels) {
        for (int i : ms.ci) EXPECT_NE(u, double(i * 2));
        for (int j : ms.cj) EXPECT_NE(v, double(j * 2));
    }
}

/// Orders >= 2 alone at z_max on every lattice column of `single` (exact single scattering),
/// from add_higher_orders with this seed, every column computed, and tail pooling or not.
std::vector<double> higher_orders_green(const Asset& single, std::uint64_t seed, bool pooled) {
    Asset a = single;
    a.info.check.done = false;  // the check is not under test here
    HigherOrderSettings& h = a.info.higher_orders;
    h.paths = 512;
    h.stride = 1;
    h.seed = seed;
    h.wall = true;
    h.tail_above = pooled ? kMsTailAbove : 0.0;
    h.tail_of_mean = pooled ? kMsTailOfMean : 0.0;
    h.tail_radius = kMsTailRadius;
    add_higher_orders(a);
    std::vector<double> out;
    const int k = a.info.lattice.nk() - 1;
    for (int i = 0; i < a.info.lattice.ni; ++i)
        for (int j = 0; j < a.info.lattice.nj; ++j)
            out.push_back(a.at(i, j, k).g - single.at(i, j, k).g);
    return out;
}

TEST(MsColumns, PoolingBrightPathsCutsTheSpreadBetweenSeedsNotTheMean) {
    const Camera cam = wide(12, 9);
    const Asset single =
        bake(cam, pencils(8.0), test::test_water(), pencil_settings(Scattering::Single, 0));
    double spread_own = 0.0, spread_pooled = 0.0, sum_own = 0.0, sum_pooled = 0.0;
    const std::vector<double> a = higher_orders_green(single, 1, false);
    const std::vector<double> b = higher_orders_green(single, 2, false);
    const std::vector<double> pa = higher_orders_green(single, 1, true);
    const std::vector<double> pb = higher_orders_green(single, 2, true);
    for (std::size_t n = 0; n < a.size(); ++n) {
        spread_own += (a[n] - b[n]) * (a[n] - b[n]);
        spread_pooled += (pa[n] - pb[n]) * (pa[n] - pb[n]);
        sum_own += a[n] + b[n];
        sum_pooled += pa[n] + pb[n];
    }
    std::printf("spread between seeds: own %.4g, pooled %.4g (%.3f)\n", spread_own, spread_pooled,
                spread_pooled / spread_own);
    // Two seeds' columns differ by their noise: pooling the bright paths cuts that (squared
    // spread 0.59 x; with the roulette before each segment's next event, which made most of the
    // tail, the columns' own spread was 2.7 x larger and pooling cut it to 0.21 x: the pooled
    // spread is the same either way).
    EXPECT_LT(spread_pooled, 0.75 * spread_own);
    // It moves light between neighbouring columns, not in or out: the image's sum stays within
    // the noise of the columns' own (sqrt(spread / 2) per column, over sqrt(columns) of them).
    const double se_sum = std::sqrt(spread_own / 2.0 * double(a.size()));
    EXPECT_LT(std::abs(sum_pooled - sum_own), 3.0 * se_sum);
}

TEST(MsColumns, TailsArePooledWithinTheLightsDetail) {
    // Columns a tenth of the detail apart: the widest pooling; as far apart as the detail: none.
    EXPECT_EQ(ms_tail_radius(0.01, 0.1), kMsTailRadius);
    EXPECT_EQ(ms_tail_radius(0.1, 0.1), 0);
    EXPECT_EQ(ms_tail_radius(0.1 / 1.5, 0.1), 0);
    EXPECT_EQ(ms_tail_radius(0.1 / 2.0, 0.1), 1);
    // The pencil rig on the 12x9 camera: pixels about as wide as the detail, so none (pooling
    // there lifted a pixel beside a beam by 3.6 standard errors in
    // PencilBeamsAreResolvedBetweenColumns).
    const Camera cam = wide(12, 9);
    EXPECT_EQ(ms_tail_radius(1.0 / cam.fx, ms_detail(cam, pencils(8.0), test::test_water())), 0);
}

}  // namespace
}  // namespace deepsea
