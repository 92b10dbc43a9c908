// The schema's range checks on their own: each names the key path that the YAML reader maps
// to a line and the asset's JSON reader reports as is.
#include "deepsea/optics/schema.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace deepsea {
namespace {

template <class T>
std::string key_of(const T& x) {
    try {
        validate(x);
    } catch (const SchemaError& e) {
        return e.key();
    }
    return "";
}

Rig one_lamp() {
    Light l;
    l.name = "a";
    l.position = {0.1, 0.0, 0.0};
    l.direction = {0.0, 0.0, 2.0};  // need not be unit
    Rig r;
    r.lights = {l};
    return r;
}

TEST(Schema, CameraRanges) {
    Camera c{800, 600, 600.0, 600.0, 399.5, 299.5};
    EXPECT_EQ(key_of(c), "");
    c.height = 0;
    EXPECT_EQ(key_of(c), "camera.height");
    c = Camera{800, 600, 600.0, -1.0, 399.5, 299.5};
    EXPECT_EQ(key_of(c), "camera.fy");
}

TEST(Schema, RigRanges) {
    EXPECT_EQ(key_of(one_lamp()), "");
    EXPECT_EQ(key_of(Rig{}), "rig.lights");
    Rig r = one_lamp();
    r.lights.push_back(r.lights[0]);
    EXPECT_EQ(key_of(r), "rig.lights[1]");
    r = one_lamp();
    r.lights[0].direction = {0, 0, 0};
    EXPECT_EQ(key_of(r), "rig.lights[0].direction");
    r = one_lamp();
    r.lights[0].intensity.g = -1.0;
    EXPECT_EQ(key_of(r), "rig.lights[0].intensity");
    r = one_lamp();
    r.lights[0].rid.sigma_deg = 0.0;
    EXPECT_EQ(key_of(r), "rig.lights[0].rid.gaussian.sigma_deg");
    r = one_lamp();
    r.lights[0].rid.cutoff_deg = 181.0;
    EXPECT_EQ(key_of(r), "rig.lights[0].cutoff_deg");
    r = one_lamp();
    r.lights[0].rid.kind = Rid::Kind::Table;
    r.lights[0].rid.angle_deg = {0, 30, 60};
    r.lights[0].rid.value = {1, 0.5, 0};
    EXPECT_EQ(key_of(r), "");
    r.lights[0].rid.angle_deg = {0, 60, 30};
    EXPECT_EQ(key_of(r), "rig.lights[0].rid.table.angle_deg[2]");
    r.lights[0].rid.angle_deg = {0, 30, 60};
    r.lights[0].rid.value = {1, 0.5};
    EXPECT_EQ(key_of(r), "rig.lights[0].rid.table.value");
    r.lights[0].rid.value = {1, -0.5, 0};
    EXPECT_EQ(key_of(r), "rig.lights[0].rid.table.value[1]");
}

TEST(Schema, LampInTheCamerasNearFieldIsRefused) {
    Rig r = one_lamp();
    for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{0.01, 0.01, 0.01}, Vec3{0, 0, -0.019}}) {
        r.lights[0].position = p;
        EXPECT_EQ(key_of(r), "rig.lights[0].position") << p.x << " " << p.y << " " << p.z;
    }
    // At or beyond the limit, in any direction (behind the camera too), a lamp is fine.
    for (const Vec3 p : {Vec3{kLampNearFieldRadius, 0, 0}, Vec3{0, -0.05, 0}, Vec3{0, 0, -0.5}}) {
        r.lights[0].position = p;
        EXPECT_EQ(key_of(r), "") << p.x << " " << p.y << " " << p.z;
    }
    r.lights[0].position = {0, 0, std::nan("")};
    EXPECT_EQ(key_of(r), "rig.lights[0].position");
    // The message names the lamp, its position and the limit, on one line.
    r.lights[0].name = "centre";
    r.lights[0].position = {0, 0.01, 0};
    try {
        validate(r);
        FAIL();
    } catch (const SchemaError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("'centre'"), std::string::npos) << what;
        EXPECT_NE(what.find("[0, 0.01, 0] m"), std::string::npos) << what;
        EXPECT_NE(what.find("0.02 m"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    // The second lamp of a rig is checked as well.
    r = one_lamp();
    r.lights.push_back(r.lights[0]);
    r.lights[1].name = "b";
    r.lights[1].position = {0, 0, 0};
    EXPECT_EQ(key_of(r), "rig.lights[1].position");
}

TEST(Schema, CameraFieldOfViewIsBoundedPerAxis) {
    // Issue 29: fx 1e-4 .. 5e-324 baked for minutes into 12 GB; a huge cx likewise.
    for (const double fx : {1e-4, 1.0, 5e-324}) {
        EXPECT_EQ(key_of(Camera{320, 240, fx, 240.0, 159.5, 119.5}), "camera.fx") << fx;
        EXPECT_EQ(key_of(Camera{320, 240, 240.0, fx, 159.5, 119.5}), "camera.fy") << fx;
    }
    EXPECT_EQ(key_of(Camera{320, 240, 240.0, 240.0, 1e6, 119.5}), "camera.fx");
    EXPECT_EQ(key_of(Camera{320, 240, 240.0, 240.0, 159.5, -1e6}), "camera.fy");
    // The limit itself: the edge ray of a centred 320-pixel image at exactly 80 degrees.
    const double tan_max = std::tan(kMaxRayAngleDeg * M_PI / 180.0);
    const double f_min = 160.0 / tan_max;
    EXPECT_EQ(key_of(Camera{320, 240, f_min * (1 + 1e-9), 240.0, 159.5, 119.5}), "");
    EXPECT_EQ(key_of(Camera{320, 240, f_min * (1 - 1e-6), 240.0, 159.5, 119.5}), "camera.fx");
    // An off-centre principal point counts its far edge.
    EXPECT_EQ(key_of(Camera{320, 240, 40.0, 240.0, 319.5, 119.5}), "camera.fx");
    // The widest cameras of the tests (110 degrees across, a 3-pixel fx = 1 strip) pass.
    EXPECT_EQ(key_of(Camera{96, 72, 33.61, 33.61, 47.5, 35.5}), "");
    EXPECT_EQ(key_of(Camera{3, 1, 1.0, 1.0, 1.0, 0.0}), "");
    try {
        validate(Camera{320, 240, 1e-4, 1e-4, 159.5, 119.5});
        FAIL();
    } catch (const SchemaError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("80 degrees"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

TEST(Schema, LampIntensityAndDistanceAreBounded) {
    Rig r = one_lamp();
    for (const double v :
         {1e39, 1e308, 1e10, std::numeric_limits<double>::infinity(), std::nan("")}) {
        r.lights[0].intensity = {1.0, v, 1.0};
        EXPECT_EQ(key_of(r), "rig.lights[0].intensity") << v;
    }
    r.lights[0].intensity = Rgb(kMaxLampIntensity);
    EXPECT_EQ(key_of(r), "");
    r = one_lamp();
    for (const Vec3 p : {Vec3{1e300, 0, 0}, Vec3{1e308, 1e308, 0}, Vec3{0, 0, -100.5}}) {
        r.lights[0].position = p;
        EXPECT_EQ(key_of(r), "rig.lights[0].position") << p.x << " " << p.y << " " << p.z;
    }
    r.lights[0].position = {0, 0, kMaxLampDistance};
    EXPECT_EQ(key_of(r), "");
    r.lights[0].direction = {1e300, 1e300, 0};  // its length is not finite
    EXPECT_EQ(key_of(r), "rig.lights[0].direction");
    r.lights[0].direction = {0, std::numeric_limits<double>::infinity(), 0};
    EXPECT_EQ(key_of(r), "rig.lights[0].direction");
}

TEST(Schema, WaterRanges) {
    Water w;
    w.c = {0.4, 0.2, 0.18};
    w.b = {0.12, 0.12, 0.13};
    EXPECT_EQ(key_of(w), "");
    w.b.r = 0.5;
    EXPECT_EQ(key_of(w), "water.scattering");
    w.b.r = 0.1;
    w.phase = Phase{PhaseKind::HenyeyGreenstein, 1.0};
    EXPECT_EQ(key_of(w), "water.phase.henyey_greenstein.g");
    w.phase = Phase{PhaseKind::HenyeyGreenstein, 0.9};
    w.forward = ForwardScatter{true, {0.5, 0.1, 0.1}, 0.05};
    EXPECT_EQ(key_of(w), "water.forward_scatter.G");
    w.forward = ForwardScatter{true, {0.3, 0.1, 0.1}, -1.0};
    EXPECT_EQ(key_of(w), "water.forward_scatter.k");
    w.forward.enabled = false;  // values of a disabled forward term are not used
    EXPECT_EQ(key_of(w), "");
}

TEST(Schema, MessagesAreKeyThenProblem) {
    try {
        validate(Camera{0, 1, 1.0, 1.0, 0.0, 0.0});
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()), "camera.width: must be > 0, got 0");
    }
}

}  // namespace
}  // namespace deepsea
