// Lamp shadows from the depth map (runtime/lamp_shadows.h) against exact geometry: a box in
// front of a wall (slab ray casts), the procedural seafloor (its height function's ray casts),
// a plane (no shadow at all), the penumbra's width, and thread counts; the default step (the
// sweep on every other pixel) against the full sweep and the seafloor's ray casts.

#include "deepsea/runtime/lamp_shadows.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "deepsea/optics/shadow.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/lamps.h"
#include "deepsea/scene/flight.h"
#include "deepsea/scene/seafloor.h"
#include "runtime_fixtures.h"

namespace deepsea {

namespace {

Rig one_lamp(const Vec3& position, double radius) {
    Rig rig;
    Light l;
    l.position = position;
    l.direction = normalize(Vec3{-0.3 * position.x, -0.3 * position.y, 1.0});
    l.radius = radius;
    rig.lights.push_back(l);
    return rig;
}

/// A block whose sides lie along the camera's rays: planar depth z in [z0, z1], x / z in
/// [a0, a1], y / z in [b0, b1]. Its thickness along each ray is z1 - z0, so the depth map's
/// thickness assumption describes it exactly.
struct Block {
    double z0, z1, a0, a1, b0, b1;
    /// The first s in [s0, s1] where o + s d is inside, or -1: each side is a half-space
    /// n . X >= 0 (or z >= z0, -z >= -z1), linear along the segment.
    double hit(const Vec3& o, const Vec3& d, double s0, double s1) const {
        const Vec3 n[6] = {{0, 0, 1},   {0, 0, -1},  {1, 0, -a0},
                           {-1, 0, a1}, {0, 1, -b0}, {0, -1, b1}};
        const double c[6] = {z0, -z1, 0, 0, 0, 0};
        for (int k = 0; k < 6; ++k) {
            const double nd = dot(n[k], d), rest = c[k] - dot(n[k], o);  // s nd >= rest
            if (std::fabs(nd) < 1e-15) {
                if (rest > 0.0) return -1.0;
            } else if (nd > 0.0) {
                s0 = std::max(s0, rest / nd);
            } else {
                s1 = std::min(s1, rest / nd);
            }
        }
        return s0 <= s1 ? s0 : -1.0;
    }
};

constexpr double kWall = 4.0;  // m: the wall behind the box
const Block kBox{2.0, 2.5, -0.15, 0.05, -0.1, 0.1};

Camera box_camera() { return Camera{300, 200, 300.0, 300.0, 149.5, 99.5}; }

/// Planar depth of the box in front of the wall z = kWall.
Image box_depth(const Camera& cam) {
    Image depth(cam.width, cam.height, 1);
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const double s = kBox.hit({0, 0, 0}, cam.ray(u, v), 0.0, kWall);  // the ray's z is 1
            depth.at(u, v) = float(s >= 0.0 ? s : kWall);
        }
    }
    return depth;
}

/// True if the segment from pixel (u, v)'s surface point to the lamp passes through the box.
bool box_shadow(const Camera& cam, const Image& depth, const Vec3& lamp, int u, int v) {
    const Vec3 p = cam.ray(u, v) * double(depth.at(u, v));
    return kBox.hit(p, lamp - p, 1e-6, 1.0) >= 0.0;
}

/// The shadows of `rig` in the frame; by default by the full sweep (step 1), the reference.
LampShadows shadows_of(const Camera& cam, const Image& depth, const Rig& rig,
                       double thickness = kDefaultShadowThickness, int step = 1) {
    LampShadows s;
    s.compute(cam, depth, rig, ShadowSettings{true, thickness, step});
    return s;
}

/// Hard shadow masks (visibility < 1/2) of the depth map against the box's ray casts: the
/// pixels that disagree, and those of them more than 3 px from a boundary of the true mask. (An
/// edge of the block is known to the depth map to half a pixel; a shadow edge cast at a grazing
/// angle magnifies that: 1-2 px where the lamp is above and beside the camera.)
struct MaskCount {
    long pixels = 0, shadowed = 0, wrong = 0, wrong_inside = 0, found = 0, both = 0;
};

MaskCount compare_box(const Camera& cam, const Vec3& lamp) {
    const Image depth = box_depth(cam);
    const LampShadows s = shadows_of(cam, depth, one_lamp(lamp, 0.0));
    const int W = cam.width, H = cam.height;
    std::vector<unsigned char> truth(std::size_t(W) * H);
    for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) truth[v * W + u] = box_shadow(cam, depth, lamp, u, v);
    MaskCount m;
    for (int v = 0; v < H; ++v) {
        for (int u = 0; u < W; ++u) {
            const bool t = truth[v * W + u], got = s.row(0, v)[u] < 0.5f;
            ++m.pixels;
            m.shadowed += t;
            if (t == got) continue;
            ++m.wrong;
            bool edge = false;
            for (int dv = -3; dv <= 3; ++dv)
                for (int du = -3; du <= 3; ++du) {
                    const int x = std::clamp(u + du, 0, W - 1), y = std::clamp(v + dv, 0, H - 1);
                    edge = edge || truth[y * W + x] != t;
                }
            m.wrong_inside += !edge;
        }
    }
    return m;
}

}  // namespace

TEST(LampShadows, BoxCastsItsShadowWhereRaysThroughTheBoxSay) {
    const Camera cam = box_camera();
    // lamps beside the camera (parallel epipolar lines), behind it and in front of it (an
    // epipole outside and inside the image)
    for (const Vec3& lamp : {Vec3{-0.5, 0.0, 0.0}, Vec3{0.3, -0.4, 0.0}, Vec3{-0.5, -0.3, -0.2},
                             Vec3{0.4, 0.2, 0.3}, Vec3{0.05, 0.03, 0.5}}) {
        const MaskCount m = compare_box(cam, lamp);
        std::printf(
            "lamp [%g, %g, %g]: %ld of %ld px shadowed, %ld disagree (%ld off the "
            "boundary)\n",
            lamp.x, lamp.y, lamp.z, m.shadowed, m.pixels, m.wrong, m.wrong_inside);
        EXPECT_GT(m.shadowed, 500);
        EXPECT_LT(double(m.wrong), 0.005 * double(m.pixels));
        EXPECT_EQ(m.wrong_inside, 0);
    }
}

TEST(LampShadows, ShadowOfTheBoxEdgeIsWhereTheLineThroughTheLampSays) {
    // The lamp at x = -0.5 in the camera's plane: the box's front right edge (x = 0.1, z = 2)
    // shadows the wall up to X = -0.5 + 0.6 * kWall / 2 = 0.7 m, pixel u = cx + fx 0.7 / 4.
    const Camera cam = box_camera();
    const LampShadows s = shadows_of(cam, box_depth(cam), one_lamp({-0.5, 0.0, 0.0}, 0.0));
    const int v = 100;
    const double edge = cam.cx + cam.fx * 0.7 / kWall;  // 202.0
    for (int u = 166; u < cam.width; ++u) {
        const bool shadowed = s.row(0, v)[u] < 0.5f;
        if (u != 202) {  // 202: on the edge
            EXPECT_EQ(shadowed, u < edge) << "u = " << u;
        }
    }
}

namespace {

/// The fraction of a lamp's disc (radius R at L, facing P) that P sees past the block: 2000
/// points on a Fermat spiral, each segment cast through the block.
double disc_visibility(const Vec3& p, const Vec3& L, double R) {
    const Vec3 w = normalize(L - p);
    const Vec3 e1 = normalize(cross(w, std::fabs(w.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0}));
    const Vec3 e2 = cross(w, e1);
    const int n = 2000;
    int seen = 0;
    for (int k = 0; k < n; ++k) {
        const double r = R * std::sqrt((k + 0.5) / n), phi = k * 2.399963229728653;
        const Vec3 q = L + e1 * (r * std::cos(phi)) + e2 * (r * std::sin(phi));
        seen += kBox.hit(p, q - p, 1e-6, 1.0) < 0.0;
    }
    return double(seen) / n;
}

}  // namespace

TEST(LampShadows, PenumbraFollowsTheLampsDiscAndWidensWithItsRadius) {
    // Edge at z = 2 m, wall at 4 m: the penumbra on the wall is 2 R d_o / s_l = 2 R wide,
    // 2 R fx / kWall = 150 R px. Along the row through the block's middle, visibility against
    // the lamp's disc sampled through the block.
    const Camera cam = box_camera();
    const Image depth = box_depth(cam);
    const Vec3 L{-0.5, 0.0, 0.0};
    const int v = 100;
    double last = 0.0;
    for (double R : {0.01, 0.03, 0.06, 0.12}) {
        const LampShadows s = shadows_of(cam, depth, one_lamp(L, R));
        double width = 0.0, worst = 0.0;
        for (int u = 166; u < cam.width; ++u) {
            const float x = s.row(0, v)[u];
            width += (x > 0.02f && x < 0.98f) ? 1.0 : 0.0;
            const double truth = disc_visibility(cam.ray(u, v) * double(depth.at(u, v)), L, R);
            worst = std::max(worst, std::fabs(truth - x));
        }
        std::printf(
            "R = %.2f m: penumbra %.0f px (2 R fx / z = %.1f), largest difference from "
            "the disc %.3f\n",
            R, width, 2.0 * R * cam.fx / kWall, worst);
        EXPECT_GT(width, last);
        EXPECT_LT(worst, 0.02);
        last = width;
    }
}

namespace {

/// Renders nothing but the water's own light: a zero backscatter.
struct NoBackscatter final : BackscatterSource {
    void backscatter_row(int, int n, const float*, float* out) const override {
        std::fill_n(out, 3 * n, 0.0f);
    }
};

}  // namespace

TEST(LampShadows, PlaneHasNoShadowAndTheSameDirectSignal) {
    const Camera cam = testing::small_camera();
    Image depth(cam.width, cam.height, 1), rgb(cam.width, cam.height, 3);
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
            depth.at(u, v) = float(3.0 / (1.0 - 0.3 * cam.ray_x(u) + 0.2 * cam.ray_y(v)));
            for (int c = 0; c < 3; ++c) rgb.at(u, v, c) = 0.3f + 0.1f * float(c);
        }
    Rig rig = testing::two_lamps();
    rig.lights.push_back(one_lamp({0.1, -0.2, 0.3}, 0.05).lights[0]);  // an epipole in view
    const LampShadows s = shadows_of(cam, depth, rig);
    for (std::size_t l = 0; l < rig.lights.size(); ++l)
        for (int v = 0; v < cam.height; ++v)
            for (int u = 0; u < cam.width; ++u) ASSERT_EQ(s.row(l, v)[u], 1.0f) << u << " " << v;

    const Water water = jerlov_water("IB");
    const NoBackscatter bs;
    const AnalyticLamps off(rig, water), on(rig, water, {}, ShadowSettings{true});
    Layers a, b;
    const Frame frame{rgb, depth};
    Compositor(cam, water, off, bs).composite(a, frame);
    Compositor(cam, water, on, bs).composite(b, frame);
    EXPECT_EQ(std::memcmp(a.direct.data.data(), b.direct.data.data(),
                          a.direct.data.size() * sizeof(float)),
              0);
}

namespace {

/// A frame of the procedural seafloor seen from `pitch_deg`, and every pixel's hard shadow of
/// the lamp at `lamp` (camera frame) both from the depth map and by a ray cast in the seafloor's
/// own geometry. Counts the pixels the lamp lights (its side of the true surface).
MaskCount compare_seafloor(double pitch_deg, const Vec3& lamp, double thickness, std::uint64_t seed,
                           int step = 1) {
    // a close survey: 1 m above a floor of twice and a half the usual relief (nodules up to
    // 11 cm high), where the lamps' shadows are several pixels long; `step` times the pixels
    // along each axis, so that the samples swept are the same
    FlightParams fp;
    fp.camera = Camera{240 * step,
                       180 * step,
                       200.0 * step,
                       200.0 * step,
                       119.5 * step + (step - 1) * 0.5,
                       89.5 * step + (step - 1) * 0.5};
    fp.pitch_deg = pitch_deg;
    fp.altitude = 1.0;
    fp.seed = seed;
    fp.relief = 2.5;
    const Frame frame = render_flight_frame(fp, 0);
    const FlightPose pose = flight_pose(fp, 0);
    const Seafloor floor(fp.seed, fp.relief);
    auto world = [&](const Vec3& r) {
        return pose.right * r.x + pose.down * r.y + pose.forward * r.z;
    };
    const Vec3 lw = pose.origin + world(lamp);
    const LampShadows s = shadows_of(fp.camera, frame.depth, one_lamp(lamp, 0.0), thickness, step);
    MaskCount m;
    for (int v = 0; v < fp.camera.height; ++v) {
        for (int u = 0; u < fp.camera.width; ++u) {
            const double z = frame.depth.at(u, v);
            if (!(z > 0.0)) continue;
            const Vec3 p = pose.origin + world(fp.camera.ray(u, v)) * z;
            const double e = 1e-3;
            const Vec3 n =
                normalize(Vec3{floor.height(p.x - e, p.y) - floor.height(p.x + e, p.y),
                               floor.height(p.x, p.y - e) - floor.height(p.x, p.y + e), 2.0 * e});
            const Vec3 to_lamp = lw - p;
            if (!(dot(n, to_lamp) > 0.0)) continue;  // the lamp lights the other side
            const Vec3 start = p + n * 2e-3;
            const bool truth = floor.intersect(start, lw - start, length(lw - start)) >= 0.0;
            const bool got = s.row(0, v)[u] < 0.5f;
            ++m.pixels;
            m.shadowed += truth;
            m.found += got;
            m.both += truth && got;
            m.wrong += truth != got;
        }
    }
    return m;
}

}  // namespace

/// The seafloor's masks against its ray casts for lamps beside, below and above-and-ahead of
/// the camera, the floor seen straight down and pitched forward: hard shadows (radius 0), the
/// default thickness, swept on every step-th pixel of a frame of step times the pixels.
void seafloor_masks(int step) {
    const char* env = std::getenv("DEEPSEA_SHADOW_THICKNESS");  // to compare thicknesses
    const double thickness = env ? std::atof(env) : kDefaultShadowThickness;
    MaskCount total;
    for (double pitch : {0.0, 45.0}) {
        for (const Vec3& lamp : {Vec3{-0.6, 0.0, 0.0}, Vec3{0.0, 0.6, 0.0}, Vec3{0.5, -0.3, 0.3}}) {
            const MaskCount m = compare_seafloor(pitch, lamp, thickness, 1, step);
            const double agree = 1.0 - double(m.wrong) / double(m.pixels);
            std::printf(
                "step %d, pitch %2.0f, lamp [%g, %g, %g]: %.1f %% of lit-side pixels shadowed; "
                "masks agree on %.2f %% (of the shadowed %.1f %% found, of those found "
                "%.1f %% shadowed)\n",
                step, pitch, lamp.x, lamp.y, lamp.z, 100.0 * m.shadowed / m.pixels, 100.0 * agree,
                100.0 * m.both / std::max(1L, m.shadowed), 100.0 * m.both / std::max(1L, m.found));
            EXPECT_GE(agree, 0.97);
            total.pixels += m.pixels;
            total.shadowed += m.shadowed;
        }
    }
    EXPECT_GT(total.shadowed, total.pixels / 100);  // scenes with shadows to find
}

TEST(LampShadows, SeafloorShadowsAgreeWithRaysThroughTheHeightField) { seafloor_masks(1); }

TEST(LampShadows, SeafloorShadowsOnEveryOtherPixelAgreeAtTwiceTheResolution) {
    // The default step's samples are the full sweep's pixels above: what it loses is what the
    // frame shows finer than two pixels.
    seafloor_masks(kDefaultShadowStep);
}

TEST(LampShadows, EveryOtherPixelAgreesWithTheFullSweep) {
    // The demo's view of a close survey (the camera pitched 40 degrees, 1 m up, relief 2.5) at
    // 400x400, the demo's lamps and two more (below the camera; ahead of it, its epipole in
    // view), the default radius: the default step against the full sweep, pixel by pixel.
    FlightParams fp;
    fp.camera = Camera{400, 400, 300.0, 300.0, 199.5, 199.5};
    fp.pitch_deg = 40.0;
    fp.altitude = 1.0;
    fp.relief = 2.5;
    const Frame frame = render_flight_frame(fp, 0);
    Rig rig = testing::two_lamps();
    rig.lights.push_back(one_lamp({0.0, 0.6, 0.0}, kDefaultLampRadius).lights[0]);
    rig.lights.push_back(one_lamp({0.1, 0.3, 0.4}, kDefaultLampRadius).lights[0]);
    const LampShadows full = shadows_of(fp.camera, frame.depth, rig);
    const LampShadows coarse =
        shadows_of(fp.camera, frame.depth, rig, kDefaultShadowThickness, kDefaultShadowStep);
    const int W = fp.camera.width, H = fp.camera.height;
    for (std::size_t l = 0; l < rig.lights.size(); ++l) {
        long pixels = 0, shadowed = 0, wrong = 0, far = 0;
        double diff = 0.0;
        for (int v = 0; v < H; ++v) {
            for (int u = 0; u < W; ++u) {
                if (!has_surface(frame.depth.at(u, v))) continue;
                const float a = full.row(l, v)[u], b = coarse.row(l, v)[u];
                ++pixels;
                shadowed += a < 0.5f;
                diff += std::fabs(double(a) - double(b));
                if ((a < 0.5f) == (b < 0.5f)) continue;
                ++wrong;
                // more than step + 1 px from the full sweep's mask boundary
                const int reach = kDefaultShadowStep + 1;
                bool edge = false;
                for (int dv = -reach; dv <= reach; ++dv)
                    for (int du = -reach; du <= reach; ++du) {
                        const int x = std::clamp(u + du, 0, W - 1),
                                  y = std::clamp(v + dv, 0, H - 1);
                        edge = edge || (full.row(l, y)[x] < 0.5f) != (a < 0.5f);
                    }
                far += !edge;
            }
        }
        const double agree = 1.0 - double(wrong) / double(pixels);
        std::printf(
            "lamp %zu: %.1f %% shadowed; masks agree on %.2f %% (%ld px differ, %ld more than "
            "step + 1 px from a boundary), mean |visibility difference| %.4f\n",
            l, 100.0 * shadowed / pixels, 100.0 * agree, wrong, far, diff / pixels);
        EXPECT_GE(agree, 0.98);
        EXPECT_LT(diff / pixels, 0.02);
        EXPECT_EQ(far, 0);  // the differences are the boundaries' place, not shadows lost
    }
}

TEST(LampShadows, IdenticalAtAnyThreadCount) {
    FlightParams fp;
    fp.camera = Camera{160, 120, 140.0, 140.0, 79.5, 59.5};
    fp.pitch_deg = 40.0;
    fp.relief = 1.5;
    const Frame frame = render_flight_frame(fp, 0);
    Rig rig = testing::two_lamps();
    rig.lights.push_back(one_lamp({0.1, 0.3, 0.4}, 0.05).lights[0]);
    const LampShadows all =
        shadows_of(fp.camera, frame.depth, rig, kDefaultShadowThickness, kDefaultShadowStep);
    LampShadows one;
    tbb::task_arena(1).execute(
        [&] { one.compute(fp.camera, frame.depth, rig, ShadowSettings{true}); });
    for (std::size_t l = 0; l < rig.lights.size(); ++l) {
        const Image& a = all.visibility(l);
        const Image& b = one.visibility(l);
        EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0);
    }
}

TEST(LampShadows, TransposedFrameGivesTheTransposedVisibility) {
    // A lamp beside the camera sweeps lines along the rows, which run in the transposed frame
    // (lamp_shadows.cpp); the same lamp, frame and camera transposed beforehand sweep columns
    // directly. The two must be each other's transpose, bit for bit (a non-square frame, so
    // that a width taken for a height shows).
    FlightParams fp;
    fp.camera = Camera{240, 180, 200.0, 210.0, 119.5, 89.5};
    fp.pitch_deg = 45.0;  // the seafloor test's close survey
    fp.altitude = 1.0;
    fp.relief = 2.5;
    const Frame frame = render_flight_frame(fp, 0);
    const Camera& cam = fp.camera;
    const Camera camt{cam.height, cam.width, cam.fy, cam.fx, cam.cy, cam.cx};
    Image deptht(cam.height, cam.width, 1);
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) deptht.at(v, u) = frame.depth.at(u, v);
    const Vec3 lamp{-0.6, 0.05, 0.0};
    const LampShadows a = shadows_of(cam, frame.depth, one_lamp(lamp, 0.04));
    const LampShadows b = shadows_of(camt, deptht, one_lamp({lamp.y, lamp.x, lamp.z}, 0.04));
    long differ = 0, shadowed = 0;
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
            differ += a.visibility(0).at(u, v) != b.visibility(0).at(v, u);
            shadowed += a.visibility(0).at(u, v) < 0.5f;
        }
    std::printf("transposed: %ld of %d px shadowed, %ld differ\n", shadowed, cam.width * cam.height,
                differ);
    EXPECT_GT(shadowed, 0);
    EXPECT_EQ(differ, 0);
}

}  // namespace deepsea
