// The procedural seafloor: ray-marching correctness against brute force, slope and height
// bounds, albedo range and variation.

#include "deepsea/scene/seafloor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "../../../src/scene/noise.h"

namespace deepsea {
namespace {

constexpr double kPi = 3.14159265358979323846;

double luminance(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

TEST(Seafloor, MarcherFindsTheFirstHitLikeBruteForce) {
    // Oblique rays over nodules are where a marcher can step through a bump and find the
    // ground behind it. Brute force: 0.2 mm steps through the whole relief band.
    const Seafloor floor(7, 1.0);
    int checked = 0, occluded_by_bump = 0;
    for (int i = 0; i < 500; ++i) {
        const double ang = (20.0 + 60.0 * scene_detail::cell_unit(99, i)) * kPi / 180.0;
        const double az = 2.0 * kPi * scene_detail::cell_unit(98, i);
        const Vec3 o{0.37 * i, 0.11 * i, 1.5};
        const Vec3 d{std::sin(ang) * std::cos(az), std::sin(ang) * std::sin(az), -std::cos(ang)};
        const double t = floor.intersect(o, d, 50.0);
        ASSERT_GT(t, 0.0);
        const double t0 = (floor.max_height() - o.z) / d.z;
        double brute = -1.0;
        for (double s = t0; s < t + 1e-3; s += 2e-4) {
            const Vec3 p = o + d * s;
            if (p.z <= floor.height(p.x, p.y)) {
                brute = s;
                break;
            }
        }
        ASSERT_GT(brute, 0.0);
        ASSERT_GE(brute, t - 1e-9) << "ray " << i << ": the marcher missed an earlier hit";
        ASSERT_LE(brute, t + 2e-4 + 1e-9) << "ray " << i;
        ++checked;
        const Vec3 hit = o + d * t;
        occluded_by_bump += floor.sample(hit.x, hit.y).material != SeafloorMaterial::Sand;
    }
    EXPECT_EQ(checked, 500);
    EXPECT_GT(occluded_by_bump, 10);  // some rays did hit nodules or rocks
}

TEST(Seafloor, HeightAndSlopeStayWithinTheirBounds) {
    // The marcher's step sizes rely on max_slope(); the noise constants on measured bounds.
    double max_noise = 0.0, max_noise_slope = 0.0;
    const double e = 1e-6;
    for (int i = 0; i < 200000; ++i) {
        const double x = 40.0 * scene_detail::cell_unit(1, i);
        const double y = 40.0 * scene_detail::cell_unit(2, i);
        const std::uint64_t salt = std::uint64_t(i % 7);
        max_noise = std::max(max_noise, std::fabs(scene_detail::gradient_noise(salt, x, y)));
        const double gx = (scene_detail::gradient_noise(salt, x + e, y) -
                           scene_detail::gradient_noise(salt, x - e, y)) /
                          (2 * e);
        const double gy = (scene_detail::gradient_noise(salt, x, y + e) -
                           scene_detail::gradient_noise(salt, x, y - e)) /
                          (2 * e);
        max_noise_slope = std::max(max_noise_slope, std::hypot(gx, gy));
    }
    EXPECT_LT(max_noise, scene_detail::kNoiseMax);
    EXPECT_LT(max_noise_slope, scene_detail::kNoiseSlope);

    for (std::uint64_t seed : {1u, 2u, 3u}) {
        const Seafloor floor(seed, 1.0);
        double lo = 1e9, hi = -1e9, slope = 0.0;
        for (int i = 0; i < 100000; ++i) {
            const double x = 30.0 * scene_detail::cell_unit(seed, i);
            const double y = 30.0 * scene_detail::cell_unit(seed + 10, i);
            const double h = floor.height(x, y);
            lo = std::min(lo, h);
            hi = std::max(hi, h);
            const double gx = (floor.height(x + e, y) - floor.height(x - e, y)) / (2 * e);
            const double gy = (floor.height(x, y + e) - floor.height(x, y - e)) / (2 * e);
            slope = std::max(slope, std::hypot(gx, gy));
        }
        EXPECT_GE(lo, floor.min_height());
        EXPECT_LE(hi, floor.max_height());
        EXPECT_LT(slope, floor.max_slope());
        EXPECT_GT(hi - lo, 0.05);  // there is relief: undulation, ripples, nodules
    }
    const Seafloor flat(1, 0.0);
    EXPECT_EQ(flat.height(12.3, -4.5), 0.0);
    EXPECT_EQ(flat.max_slope(), 0.0);
}

TEST(Seafloor, AlbedoIsPlausibleAndVaried) {
    const Seafloor floor(3, 1.0);
    double sand_sum = 0.0, nodule_sum = 0.0, max_c = 0.0, min_c = 1.0;
    int sand = 0, nodule = 0, other = 0;
    const int n = 300;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double x = 0.01 * i + 0.0031, y = 0.01 * j - 0.0017;
            const SeafloorSample s = floor.sample(x, y);
            const Rgb a = floor.albedo(x, y);
            ASSERT_EQ(a.r, s.albedo.r);  // the two entry points agree
            ASSERT_EQ(a.b, s.albedo.b);
            for (int c = 0; c < 3; ++c) {
                max_c = std::max(max_c, s.albedo[c]);
                min_c = std::min(min_c, s.albedo[c]);
            }
            if (s.material == SeafloorMaterial::Sand) {
                sand_sum += luminance(s.albedo);
                ++sand;
            } else if (s.material == SeafloorMaterial::Nodule) {
                nodule_sum += luminance(s.albedo);
                ++nodule;
            } else {
                ++other;
            }
        }
    }
    EXPECT_GE(min_c, 0.0);
    EXPECT_LE(max_c, 1.0);
    EXPECT_GT(sand, n * n / 2);
    EXPECT_GT(nodule, n * n / 100);  // a 3 m x 3 m patch has nodules
    EXPECT_GT(other, 0);             // and a shell, rock or bright speck
    const double sand_mean = sand_sum / sand, nodule_mean = nodule_sum / nodule;
    EXPECT_GT(sand_mean, 0.2);
    EXPECT_LT(sand_mean, 0.45);
    EXPECT_GT(nodule_mean, 0.03);
    EXPECT_LT(nodule_mean, 0.1);
}

TEST(Seafloor, FlatTextureStaysThereWhenReliefIsOff) {
    // relief only scales heights: the albedo at a world point is the same.
    const Seafloor a(5, 1.0), b(5, 0.0);
    for (int i = 0; i < 1000; ++i) {
        const double x = 0.0137 * i, y = -0.0071 * i;
        const Rgb ca = a.albedo(x, y), cb = b.albedo(x, y);
        ASSERT_EQ(ca.r, cb.r);
        ASSERT_EQ(ca.g, cb.g);
        ASSERT_EQ(ca.b, cb.b);
    }
}

TEST(Seafloor, RaysThatCannotHitReturnNegative) {
    const Seafloor floor(1, 1.0);
    EXPECT_LT(floor.intersect({0, 0, 3}, {0, 0, 1}, 50.0), 0.0);      // up
    EXPECT_LT(floor.intersect({0, 0, 3}, {1, 0, 0}, 50.0), 0.0);      // level
    EXPECT_LT(floor.intersect({0, 0, 3}, {1, 0, -0.01}, 50.0), 0.0);  // beyond max range
    EXPECT_GT(floor.intersect({0, 0, 3}, {1, 0, -0.1}, 50.0), 0.0);
    EXPECT_EQ(floor.intersect({0, 0, -1}, {0, 0, -1}, 50.0), 0.0);  // starts in the ground
    EXPECT_EQ(floor.intersect({0, 0, floor.height(0, 0) - 1e-3}, {0, 0, 1}, 50.0), 0.0);
}

}  // namespace
}  // namespace deepsea
