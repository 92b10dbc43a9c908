#pragma once
// The marine-snow tests' camera, rig and clear water (marine_snow_draw_test.cpp,
// snow_scattered_light_test.cpp, snow_streaks_test.cpp).

#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"

namespace deepsea::testing {

/// Clear water that scatters little (the particles' light, not the water's, is under test).
inline Water snow_water() {
    Water w;
    w.c = {0.3, 0.1, 0.06};
    w.b = {0.05, 0.05, 0.05};
    return w;
}

inline Camera snow_camera() {
    Camera c;
    c.width = 240;
    c.height = 180;
    c.fx = c.fy = 200.0;
    c.cx = 119.5;
    c.cy = 89.5;
    return c;
}

/// Two Gaussian lamps, one with a 40 degree cutoff; with `table` the second has a tabulated
/// profile instead.
inline Rig snow_lamps(bool table) {
    Rig rig;
    Light a;
    a.position = {0.4, -0.1, 0.0};
    a.direction = normalize(Vec3{-0.25, 0.05, 1.0});
    a.intensity = {2.0, 1.5, 1.0};
    a.rid.sigma_deg = 30.0;
    a.rid.cutoff_deg = 40.0;
    rig.lights.push_back(a);
    Light b = a;
    b.position = {-0.4, 0.1, 0.05};
    b.direction = normalize(Vec3{0.2, 0.1, 1.0});
    b.intensity = {1.0, 1.2, 1.4};
    b.rid.cutoff_deg = 180.0;
    if (table) {
        b.rid.kind = Rid::Kind::Table;
        b.rid.angle_deg = {0, 10, 25, 50, 70};
        b.rid.value = {1.0, 0.9, 0.6, 0.1, 0.0};
    }
    rig.lights.push_back(b);
    return rig;
}

}  // namespace deepsea::testing
