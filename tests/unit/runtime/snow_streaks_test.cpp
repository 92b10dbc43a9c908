// Marine snow's motion streaks (marine_snow_draw.cpp, docs/snow-shadows.md "Motion streaks"):
// a lone particle's streak keeps the still disc's light, is centred where the particle is seen
// at the frame's time, and for a camera translating across the view runs along the image motion
// for f d / z pixels (d the distance moved while the shutter is open); longer ones are clamped;
// off without a pose or with streaks off; the same image at any thread count.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

#include "deepsea/optics/camera_motion.h"
#include "deepsea/runtime/marine_snow.h"
#include "snow_fixtures.h"

namespace deepsea {

namespace {

SnowSettings streak_settings() {
    SnowSettings s;
    s.snow = snow_preset("abyssal");
    s.snow.concentration = 2.0;  // a few particles in view
    s.snow.max_distance_m = 2.0;
    s.streaks = true;
    return s;
}

/// A camera looking along a tilted axis from `origin` (not the world's axes, so that the
/// shutter's poses go through the world and back).
CameraPose tilted_pose(const Vec3& origin) {
    const Vec3 f = normalize(Vec3{0.3, -0.2, 1.0});
    const Vec3 r = normalize(cross(Vec3{0.1, 1.0, 0.05}, f));
    return {origin, r, cross(f, r), f};
}

/// The camera moved by `d` (camera-frame metres) while the shutter is open, centred on `p`.
Shutter moving(const CameraPose& p, const Vec3& d) {
    const Vec3 w = p.right * d.x + p.down * d.y + p.forward * d.z;
    Shutter s{p, p};
    s.open.origin = p.origin - w * 0.5;
    s.close.origin = p.origin + w * 0.5;
    return s;
}

/// Light-weighted moments of the green channel in a box: sum, centroid, covariance.
struct Moments {
    double sum = 0, mu = 0, mv = 0, cuu = 0, cvv = 0, cuv = 0;
};

Moments moments(const Image& img, int u0, int v0, int u1, int v1) {
    Moments m;
    for (int v = v0; v <= v1; ++v)
        for (int u = u0; u <= u1; ++u) {
            const double w = img.at(u, v, 1);
            m.sum += w;
            m.mu += w * u;
            m.mv += w * v;
        }
    m.mu /= m.sum;
    m.mv /= m.sum;
    for (int v = v0; v <= v1; ++v)
        for (int u = u0; u <= u1; ++u) {
            const double w = img.at(u, v, 1) / m.sum;
            m.cuu += w * (u - m.mu) * (u - m.mu);
            m.cvv += w * (v - m.mv) * (v - m.mv);
            m.cuv += w * (u - m.mu) * (v - m.mv);
        }
    return m;
}

/// Draws one frame of `s` into a zeroed final image, over open water.
Image draw(const MarineSnow& snow, const Camera& cam) {
    const Image depth(cam.width, cam.height, 1);  // 0: open water
    Image final(cam.width, cam.height, 3);
    snow.draw(cam, depth, final, nullptr, nullptr);
    return final;
}

/// Checks every lone particle's streak against the still disc and the analytic streak of a
/// camera moving by `d` across the view; returns how many were checked. `soft`: a lens that
/// blurs every particle to a disc wider than a pixel (drawn as swept coverage), else the
/// default lens (most particles smaller than a pixel: drawn as bilinear samples).
int check_streaks(const Vec3& d, int want, bool soft) {
    const Camera cam = testing::snow_camera();
    SnowSettings s = streak_settings();
    if (soft) {
        s.f_number = 0.5;
        s.pixel_pitch_um = 20.0;
        s.focus_distance_m = 0.2;
    }
    const ThinLens lens{cam.fx, s.pixel_pitch_um, s.f_number, s.focus_distance_m};
    MarineSnow snow(s, testing::snow_lamps(false), testing::snow_water());
    int checked = 0;
    for (int seed = 0; seed < 300 && checked < want; ++seed) {
        const CameraPose pose = tilted_pose({0.7 * seed, -0.3 * seed, 0.2 * seed});
        snow.set_frame(0, pose);
        const Image still = draw(snow, cam);
        snow.set_frame(0, pose, moving(pose, d));
        const Image streak = draw(snow, cam);
        const auto particles = snow_particles(s, cam, 0, pose);
        // The expected streak of each: image motion -f d / z (the camera moves, the world
        // stays), clamped to kMaxSnowStreakPx.
        const auto extent = [&](const SnowParticle& p, double* len) {
            const Vec3& X = p.position;
            const double l = cam.fx * std::hypot(d.x, d.y) / X.z;
            if (len) *len = l;
            return snow_disc_radius_px(cam, lens, X, p.diameter) +
                   0.5 * std::min(l, kMaxSnowStreakPx) + 3.0;
        };
        for (const SnowParticle& p : particles) {
            const Vec3& X = p.position;
            double len = 0.0;
            const double e = extent(p, &len);
            const double u = cam.fx * X.x / X.z + cam.cx, v = cam.fy * X.y / X.z + cam.cy;
            if (u - e < 0 || v - e < 0 || u + e > cam.width - 1 || v + e > cam.height - 1) continue;
            bool alone = true;
            for (const SnowParticle& o : particles) {
                const double ou = cam.fx * o.position.x / o.position.z + cam.cx;
                const double ov = cam.fy * o.position.y / o.position.z + cam.cy;
                alone &= o.id == p.id || std::hypot(ou - u, ov - v) > e + extent(o, nullptr);
            }
            if (!alone || len < 4.0) continue;
            const double radius = snow_disc_radius_px(cam, lens, X, p.diameter);
            if (soft) {
                EXPECT_GT(radius, 0.5);
            }
            const int u0 = int(u - e), u1 = int(u + e) + 1, v0 = int(v - e), v1 = int(v + e) + 1;
            const Moments a = moments(still, u0, v0, u1, v1), b = moments(streak, u0, v0, u1, v1);
            EXPECT_GT(a.sum, 0.0);
            if (!(a.sum > 0.0)) continue;
            // Energy: the streak's light is the disc's.
            EXPECT_NEAR(b.sum / a.sum, 1.0, 1e-5) << "z " << X.z;
            // Centred on the particle's place at the frame's time (motion straight across).
            EXPECT_NEAR(b.mu, a.mu, 0.05);
            EXPECT_NEAR(b.mv, a.mv, 0.05);
            // A uniform segment of length L widened by a round disc: the covariance's
            // eigenvalues differ by L^2 / 12, the larger along the motion.
            const double tr = b.cuu + b.cvv, det = b.cuu * b.cvv - b.cuv * b.cuv;
            const double gap = std::sqrt(std::max(0.0, tr * tr / 4 - det));
            const double measured = std::sqrt(12.0 * 2.0 * gap);
            const double expected = std::min(len, kMaxSnowStreakPx);
            EXPECT_NEAR(measured, expected, std::max(0.5, 0.04 * expected))
                << "z " << X.z << " radius " << radius;
            const double angle = 0.5 * std::atan2(2 * b.cuv, b.cuu - b.cvv);
            double off = std::fabs(angle - std::atan2(d.y, d.x));
            off = std::fmod(off, M_PI);
            off = std::min(off, M_PI - off);
            EXPECT_LT(off, 0.03) << "direction";
            ++checked;
        }
    }
    return checked;
}

}  // namespace

TEST(SnowStreaks, SidewaysStreakHasTheAnalyticLengthAndKeepsTheLight) {
    // 5 cm across the view in the exposure (e.g. 0.5 m/s for 100 ms): 5-100 px at 2-0.1 m.
    EXPECT_GE(check_streaks({0.05, 0.0, 0.0}, 12, false), 12);
    EXPECT_GE(check_streaks({0.05, 0.0, 0.0}, 12, true), 12);
}

TEST(SnowStreaks, DiagonalStreakFollowsTheMotion) {
    EXPECT_GE(check_streaks({0.03, -0.04, 0.0}, 12, false), 12);
    EXPECT_GE(check_streaks({0.03, -0.04, 0.0}, 12, true), 12);
}

TEST(SnowStreaks, LongStreaksAreClamped) {
    // 40 cm in the exposure: 40-800 px, most clamped to kMaxSnowStreakPx.
    EXPECT_GE(check_streaks({0.4, 0.0, 0.0}, 6, false), 6);
    EXPECT_GE(check_streaks({0.4, 0.0, 0.0}, 6, true), 6);
}

TEST(SnowStreaks, OffWithoutPoseOrSwitch) {
    const Camera cam = testing::snow_camera();
    SnowSettings s = streak_settings();
    s.snow.concentration = 200.0;
    const CameraPose pose = tilted_pose({1, 2, 3});
    const Shutter shutter = moving(pose, {0.05, 0.01, 0.02});
    MarineSnow on(s, testing::snow_lamps(false), testing::snow_water());
    s.streaks = false;
    MarineSnow off(s, testing::snow_lamps(false), testing::snow_water());
    off.set_frame(0, pose, shutter);
    on.set_frame(0, pose);
    const Image still = draw(on, cam);
    EXPECT_EQ(draw(off, cam).data, still.data);  // switched off: the still discs
    on.set_frame(0, pose, shutter);
    EXPECT_NE(draw(on, cam).data, still.data);
    on.set_frame(0, pose, Shutter{pose, pose});  // a camera at rest: the still discs
    EXPECT_EQ(draw(on, cam).data, still.data);
}

TEST(SnowStreaks, SameImageAtAnyThreadCount) {
    const Camera cam = testing::snow_camera();
    SnowSettings s = streak_settings();
    s.snow = snow_preset("plume");
    s.streaks = true;
    const CameraPose pose = tilted_pose({1, 2, 3});
    MarineSnow snow(s, testing::snow_lamps(true), testing::snow_water());
    snow.set_frame(5, pose, moving(pose, {0.03, 0.02, 0.05}));
    const Image depth = testing::slanted_floor(cam, 2.0);
    const auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        std::vector<Image> out{Image(cam.width, cam.height, 3), Image(cam.width, cam.height, 3),
                               Image(cam.width, cam.height, 1)};
        snow.draw(cam, depth, out[0], &out[1], &out[2]);
        return out;
    };
    const auto one = run(1), many = run(8);
    ASSERT_GT(snow.drawn(), 1000);
    for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one[i].data, many[i].data) << i;
}

}  // namespace deepsea
