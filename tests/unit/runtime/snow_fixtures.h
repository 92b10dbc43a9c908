#pragma once
// The marine-snow tests' camera, rig and clear water (marine_snow_draw_test.cpp,
// snow_scattered_light_test.cpp, snow_streaks_test.cpp).

#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/core/random.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/snow_light.h"

namespace deepsea::testing {

/// Clear water that scatters little (the particles' light, not the water's, is under test).
inline Water snow_water() {
    Water w;
    w.c = {0.3, 0.1, 0.06};
    w.b = {0.05, 0.05, 0.05};
    return w;
}

/// n particles in front of the camera (depth 0.1 to 0.1 + depth_span m, in a frustum a little
/// wider than the snow camera's, diameters 0.5 to 2.5 mm), as doubles and as snow_light's rows.
struct ParticleSet {
    std::vector<Vec3> X;
    std::vector<float> x, y, z, inv, D;
    ParticleRows rows() const {
        return {int(X.size()), x.data(), y.data(), z.data(), inv.data(), D.data()};
    }
};

inline ParticleSet random_particles(Rng& rng, int n, double depth_span) {
    ParticleSet s;
    s.X.resize(static_cast<std::size_t>(n));
    for (Vec3& p : s.X) {
        p.z = 0.1 + depth_span * rng.uniform();
        p.x = (rng.uniform() - 0.5) * 1.2 * p.z;
        p.y = (rng.uniform() - 0.5) * 0.9 * p.z;
        s.x.push_back(float(p.x));
        s.y.push_back(float(p.y));
        s.z.push_back(float(p.z));
        s.inv.push_back(float(1.0 / length(p)));
        s.D.push_back(float(1e-3 * (0.5 + 2.0 * rng.uniform())));
    }
    return s;
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

/// A floor sloping away from the camera's top row: planar depth 0.5 m there, 0.5 + span m at
/// the bottom, so that some particles and parts of discs lie behind it.
inline Image slanted_floor(const Camera& cam, double span) {
    Image depth(cam.width, cam.height, 1);
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) depth.at(u, v) = float(0.5 + span * v / cam.height);
    return depth;
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
