// Seafloor flights: determinism at any thread count, exact depth on analytic floors, hits on
// the surface, colour variation, camera motion and pose, parameter checks.

#include "deepsea/scene/flight.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/scene/seafloor.h"

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

TEST(Flight, SameSeedIsBitIdenticalAtAnyThreadCount) {
    FlightParams f = small_flight();
    f.pitch_deg = 25.0;
    const Frame a = render_flight_frame(f, 2, {1});
    const Frame b = render_flight_frame(f, 2, {2});
    const Frame c = render_flight_frame(f, 2, {0, 1, {}});  // all cores, one row per task
    EXPECT_EQ(a.rgb.data, b.rgb.data);
    EXPECT_EQ(a.depth.data, b.depth.data);
    EXPECT_EQ(a.rgb.data, c.rgb.data);
    EXPECT_EQ(a.depth.data, c.depth.data);
}

TEST(Flight, DifferentSeedsDiffer) {
    FlightParams f = small_flight();
    const Frame a = render_flight_frame(f, 0);
    f.seed = 2;
    const Frame b = render_flight_frame(f, 0);
    std::size_t rgb_diff = 0, depth_diff = 0;
    for (std::size_t i = 0; i < a.rgb.data.size(); ++i) rgb_diff += a.rgb.data[i] != b.rgb.data[i];
    for (std::size_t i = 0; i < a.depth.data.size(); ++i) {
        depth_diff += a.depth.data[i] != b.depth.data[i];
    }
    EXPECT_GT(rgb_diff, a.rgb.data.size() * 9 / 10);
    EXPECT_GT(depth_diff, a.depth.data.size() * 9 / 10);
}

TEST(Flight, FlatFloorStraightDownIsAltitudeEverywhere) {
    FlightParams f = small_flight();
    f.relief = 0.0;
    f.altitude = 2.7;
    const Frame frame = render_flight_frame(f, 3);
    for (int v = 0; v < f.camera.height; ++v) {
        for (int u = 0; u < f.camera.width; ++u) {
            ASSERT_NEAR(frame.depth.at(u, v), 2.7, 2.7e-6) << u << "," << v;
        }
    }
}

TEST(Flight, FlatFloorPitchedMatchesRayPlaneIntersection) {
    for (const double pitch : {-20.0, 15.0, 40.0, 62.0}) {
        FlightParams f = small_flight();
        f.relief = 0.0;
        f.pitch_deg = pitch;
        f.altitude = 3.0;
        const Frame frame = render_flight_frame(f, 1);
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

TEST(Flight, ReliefDepthAtCentreIsAltitudeMinusFloorHeight) {
    FlightParams f = small_flight();
    const Seafloor floor(f.seed, f.relief);
    for (int index : {0, 5, 11}) {
        const Frame frame = render_flight_frame(f, index);
        const FlightPose pose = flight_pose(f, index);
        const double h = floor.height(pose.origin.x, pose.origin.y);
        const double depth = frame.depth.at(80, 60);
        EXPECT_NEAR(depth, f.altitude - h, 1e-5);
        EXPECT_GE(depth, f.altitude - floor.max_height());
        EXPECT_LE(depth, f.altitude - floor.min_height());
        EXPECT_LT(std::fabs(depth - f.altitude), 0.4);  // within the relief amplitude
    }
}

TEST(Flight, EveryHitLiesOnTheSurface) {
    FlightParams f = small_flight();
    f.pitch_deg = 45.0;
    const Seafloor floor(f.seed, f.relief);
    const FlightPose pose = flight_pose(f, 4);
    const Frame frame = render_flight_frame(f, 4);
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

TEST(Flight, RenderedColourHasRealVariation) {
    FlightParams f = small_flight();
    const Frame frame = render_flight_frame(f, 0);
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

TEST(Flight, ConsecutiveFramesShowTheFloorMovedByTheSpeed) {
    // Straight down over a flat floor, the image moves down by speed * fy / altitude pixels
    // per frame (image up is the direction of travel).
    FlightParams f = small_flight();
    f.relief = 0.0;
    f.speed = 0.25;  // 10 rows at fy = 120, altitude 3
    const Frame a = render_flight_frame(f, 6), b = render_flight_frame(f, 7);
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
    const Frame c = render_flight_frame(f, 6), d = render_flight_frame(f, 7);
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

TEST(Flight, PoseFollowsTheConventions) {
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

TEST(Flight, BadParametersThrowConfigError) {
    auto expect_bad = [](auto change) {
        FlightParams f = small_flight();
        change(f);
        EXPECT_THROW(render_flight_frame(f, 0), ConfigError);
    };
    EXPECT_THROW(render_flight_frame(small_flight(), 0, {-2}), ConfigError);
    expect_bad([](FlightParams& f) { f.camera.width = 0; });
    expect_bad([](FlightParams& f) { f.camera.fy = 0.0; });
    expect_bad([](FlightParams& f) { f.altitude = 0.0; });
    expect_bad([](FlightParams& f) { f.altitude = std::nan(""); });
    expect_bad([](FlightParams& f) { f.pitch_deg = 90.0; });
    expect_bad([](FlightParams& f) { f.relief = -1.0; });
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
