// Procedural seafloor: determinism, exact depth on analytic floors, ray-marching correctness
// against brute force, slope and height bounds, albedo range and variation, camera motion.

#include "deepsea/scene/seafloor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../../../src/scene/noise.h"
#include "deepsea/core/error.h"

namespace deepsea {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A small camera with the authors' 67 degree field of view (fx = width / 1.33), integer
/// principal point so that pixel (cx, cy) looks along the optical axis.
FlightParams small_flight() {
    FlightParams f;
    f.camera.width = 160;
    f.camera.height = 120;
    f.camera.fx = f.camera.fy = 120.0;
    f.camera.cx = 80.0;
    f.camera.cy = 60.0;
    return f;
}

Vec3 world_ray(const FlightPose& pose, const Vec3& r) {
    return pose.right * r.x + pose.down * r.y + pose.forward * r.z;
}

double luminance(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

TEST(Seafloor, SameSeedIsBitIdenticalAtAnyThreadCount) {
    FlightParams f = small_flight();
    f.pitch_deg = 25.0;
    f.threads = 1;
    const RgbdFrame a = render_flight_frame(f, 2);
    f.threads = 2;
    const RgbdFrame b = render_flight_frame(f, 2);
    f.threads = 0;
    const RgbdFrame c = render_flight_frame(f, 2);
    EXPECT_EQ(a.rgb.data, b.rgb.data);
    EXPECT_EQ(a.depth.data, b.depth.data);
    EXPECT_EQ(a.rgb.data, c.rgb.data);
    EXPECT_EQ(a.depth.data, c.depth.data);
}

TEST(Seafloor, DifferentSeedsDiffer) {
    FlightParams f = small_flight();
    const RgbdFrame a = render_flight_frame(f, 0);
    f.seed = 2;
    const RgbdFrame b = render_flight_frame(f, 0);
    std::size_t rgb_diff = 0, depth_diff = 0;
    for (std::size_t i = 0; i < a.rgb.data.size(); ++i) rgb_diff += a.rgb.data[i] != b.rgb.data[i];
    for (std::size_t i = 0; i < a.depth.data.size(); ++i) {
        depth_diff += a.depth.data[i] != b.depth.data[i];
    }
    EXPECT_GT(rgb_diff, a.rgb.data.size() * 9 / 10);
    EXPECT_GT(depth_diff, a.depth.data.size() * 9 / 10);
}

TEST(Seafloor, FlatFloorStraightDownIsAltitudeEverywhere) {
    FlightParams f = small_flight();
    f.relief = 0.0;
    f.altitude = 2.7;
    const RgbdFrame frame = render_flight_frame(f, 3);
    for (int v = 0; v < f.camera.height; ++v) {
        for (int u = 0; u < f.camera.width; ++u) {
            ASSERT_NEAR(frame.depth.at(u, v), 2.7, 2.7e-6) << u << "," << v;
        }
    }
}

TEST(Seafloor, FlatFloorPitchedMatchesRayPlaneIntersection) {
    for (const double pitch : {-20.0, 15.0, 40.0, 62.0}) {
        FlightParams f = small_flight();
        f.relief = 0.0;
        f.pitch_deg = pitch;
        f.altitude = 3.0;
        const RgbdFrame frame = render_flight_frame(f, 1);
        const double p = pitch * kPi / 180.0;
        int hits = 0, misses = 0;
        for (int v = 0; v < f.camera.height; v += 7) {
            for (int u = 0; u < f.camera.width; u += 9) {
                const Vec3 r = f.camera.ray(u, v);
                // Camera y is (-cos p, 0, -sin p) and z is (sin p, 0, -cos p) in the world,
                // so the ray descends by (r.y sin p + cos p) per unit of z-depth.
                const double fall = r.y * std::sin(p) + std::cos(p);
                const double z = fall > 0.0 ? f.altitude / fall : 0.0;
                const bool in_range = z > 0.0 && z * length(r) <= f.max_range;
                const double expected = in_range ? z : 0.0;
                (in_range ? hits : misses)++;
                ASSERT_NEAR(frame.depth.at(u, v), expected, 1e-6 * std::max(1.0, expected))
                    << "pitch " << pitch << " pixel " << u << "," << v;
            }
        }
        EXPECT_GT(hits, 0);
        if (pitch == 62.0) {
            EXPECT_GT(misses, 0);  // the top rows see open water
        }
    }
}

TEST(Seafloor, ReliefDepthAtCentreIsAltitudeMinusFloorHeight) {
    FlightParams f = small_flight();
    const Seafloor floor(f.seed, f.relief);
    for (int index : {0, 5, 11}) {
        const RgbdFrame frame = render_flight_frame(f, index);
        const FlightPose pose = flight_pose(f, index);
        const double h = floor.height(pose.origin.x, pose.origin.y);
        const double depth = frame.depth.at(80, 60);
        EXPECT_NEAR(depth, f.altitude - h, 1e-5);
        EXPECT_GE(depth, f.altitude - floor.max_height());
        EXPECT_LE(depth, f.altitude - floor.min_height());
        EXPECT_LT(std::fabs(depth - f.altitude), 0.4);  // within the relief amplitude
    }
}

TEST(Seafloor, EveryHitLiesOnTheSurface) {
    FlightParams f = small_flight();
    f.pitch_deg = 45.0;
    const Seafloor floor(f.seed, f.relief);
    const FlightPose pose = flight_pose(f, 4);
    const RgbdFrame frame = render_flight_frame(f, 4);
    int hits = 0;
    for (int v = 0; v < f.camera.height; ++v) {
        for (int u = 0; u < f.camera.width; ++u) {
            const double t = frame.depth.at(u, v);
            if (t <= 0.0) continue;
            ++hits;
            const Vec3 p = pose.origin + world_ray(pose, f.camera.ray(u, v)) * t;
            // Depth is stored as float: allow its rounding, times the surface slope.
            ASSERT_NEAR(p.z, floor.height(p.x, p.y), 2e-5) << u << "," << v;
        }
    }
    EXPECT_EQ(hits, f.camera.width * f.camera.height);
}

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

TEST(Seafloor, RenderedColourHasRealVariation) {
    FlightParams f = small_flight();
    const RgbdFrame frame = render_flight_frame(f, 0);
    double sum = 0.0, sum2 = 0.0;
    float lo = 1.0f, hi = 0.0f;
    const int n = f.camera.width * f.camera.height;
    for (int i = 0; i < n; ++i) {
        const float* p = &frame.rgb.data[std::size_t(i) * 3];
        for (int c = 0; c < 3; ++c) {
            lo = std::min(lo, p[c]);
            hi = std::max(hi, p[c]);
        }
        const double y = luminance({p[0], p[1], p[2]});
        sum += y;
        sum2 += y * y;
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_GE(lo, 0.0f);
    EXPECT_LE(hi, 1.0f);
    EXPECT_GT(mean, 0.12);
    EXPECT_LT(mean, 0.45);
    EXPECT_GT(sd, 0.03);  // nodules, patches and grain, not a flat colour
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

/// Mean squared colour difference between frame b shifted down by `shift` rows and frame a.
double shifted_mse(const Image& a, const Image& b, int shift) {
    double sum = 0.0;
    long n = 0;
    for (int v = 0; v + shift < a.height; ++v) {
        for (int u = 0; u < a.width; ++u) {
            for (int c = 0; c < 3; ++c) {
                const double d = double(b.at(u, v + shift, c)) - a.at(u, v, c);
                sum += d * d;
                ++n;
            }
        }
    }
    return sum / n;
}

TEST(Seafloor, ConsecutiveFramesShowTheFloorMovedByTheSpeed) {
    // Straight down over a flat floor, the image moves down by speed * fy / altitude pixels
    // per frame (image up is the direction of travel).
    FlightParams f = small_flight();
    f.relief = 0.0;
    f.speed = 0.25;  // 10 rows at fy = 120, altitude 3
    const RgbdFrame a = render_flight_frame(f, 6), b = render_flight_frame(f, 7);
    int over = 0, total = 0;
    for (int v = 0; v + 10 < f.camera.height; ++v) {
        for (int u = 0; u < f.camera.width; ++u) {
            for (int c = 0; c < 3; ++c) {
                over += std::fabs(b.rgb.at(u, v + 10, c) - a.rgb.at(u, v, c)) > 1e-4f;
                ++total;
            }
        }
    }
    EXPECT_LT(over, total / 200);  // identical up to rounding at material edges

    // With relief (parallax), the best-matching shift is still about 10 rows.
    f.relief = 1.0;
    const RgbdFrame c = render_flight_frame(f, 6), d = render_flight_frame(f, 7);
    int best = -1;
    double best_mse = 1e9;
    for (int s = 0; s <= 25; ++s) {
        const double mse = shifted_mse(c.rgb, d.rgb, s);
        if (mse < best_mse) {
            best_mse = mse;
            best = s;
        }
    }
    EXPECT_NEAR(best, 10, 1);
    EXPECT_LT(best_mse, 0.2 * shifted_mse(c.rgb, d.rgb, 0));
}

TEST(Seafloor, PoseFollowsTheConventions) {
    FlightParams f = small_flight();
    f.pitch_deg = 30.0;
    f.speed = 0.5;
    const FlightPose pose = flight_pose(f, 4);
    EXPECT_DOUBLE_EQ(pose.origin.x, 2.0);
    EXPECT_DOUBLE_EQ(pose.origin.z, f.altitude);
    // Right-handed camera frame: x = y cross z; forward tilted toward +x, looking down.
    const Vec3 x = cross(pose.down, pose.forward);
    EXPECT_NEAR(x.x, pose.right.x, 1e-12);
    EXPECT_NEAR(x.y, pose.right.y, 1e-12);
    EXPECT_NEAR(x.z, pose.right.z, 1e-12);
    EXPECT_GT(pose.forward.x, 0.0);
    EXPECT_LT(pose.forward.z, 0.0);
    EXPECT_NEAR(pose.forward.x, 0.5, 1e-12);  // sin 30
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

TEST(Seafloor, BadParametersThrowConfigError) {
    auto expect_bad = [](auto change) {
        FlightParams f = small_flight();
        change(f);
        EXPECT_THROW(render_flight_frame(f, 0), ConfigError);
    };
    expect_bad([](FlightParams& f) { f.camera.width = 0; });
    expect_bad([](FlightParams& f) { f.camera.fy = 0.0; });
    expect_bad([](FlightParams& f) { f.altitude = 0.0; });
    expect_bad([](FlightParams& f) { f.altitude = std::nan(""); });
    expect_bad([](FlightParams& f) { f.pitch_deg = 90.0; });
    expect_bad([](FlightParams& f) { f.relief = -1.0; });
    expect_bad([](FlightParams& f) { f.threads = -2; });
    FlightParams f = small_flight();
    EXPECT_THROW(render_flight_frame(f, -1), ConfigError);
    // A camera within 5 cm of the floor below it: find a frame over a rise and fly low there.
    const Seafloor floor(f.seed, f.relief);
    int index = 0;
    while (index < 1000 && floor.height(flight_pose(f, index).origin.x, 0.0) < 0.02) ++index;
    ASSERT_LT(index, 1000);
    f.altitude = floor.height(flight_pose(f, index).origin.x, 0.0) + 0.02;
    EXPECT_THROW(render_flight_frame(f, index), ConfigError);
    f.frames = index + 1;  // the whole sequence is checked before anything is rendered
    EXPECT_THROW(validate_flight(f), ConfigError);
    f.relief = 0.0;
    f.altitude = 0.2;  // fine over a flat floor
    EXPECT_NO_THROW(render_flight_frame(f, 0));
    EXPECT_NO_THROW(validate_flight(f));
    f.frames = 0;
    EXPECT_THROW(validate_flight(f), ConfigError);
}

}  // namespace
}  // namespace deepsea
