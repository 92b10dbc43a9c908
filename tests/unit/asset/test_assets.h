#pragma once
// Small synthetic assets for the asset tests: values from a known function, no baking.

#include <functional>

#include "deepsea/asset/asset.h"

namespace deepsea::test {

/// Lamps "left" and "right", 0.5 m either side of the camera, their axes (-axis_x, 0, axis_z)
/// and (axis_x, 0, axis_z) normalised, Gaussian beams of sigma_deg.
inline Rig mirrored_lamps(const char* name, double axis_x, double axis_z, double sigma_deg) {
    Rig rig;
    rig.name = name;
    for (int s : {-1, 1}) {
        Light l;
        l.name = s < 0 ? "left" : "right";
        l.position = {0.5 * s, 0.0, 0.0};
        l.direction = normalize(Vec3{axis_x * s, 0.0, axis_z});
        l.intensity = {1.0, 0.9, 0.8};
        l.rid.sigma_deg = sigma_deg;
        rig.lights.push_back(l);
    }
    return rig;
}

inline Rig two_lamp_rig() { return mirrored_lamps("two-lamps", -0.51, 0.86, 35.0); }

inline Water test_water() {
    Water w;
    w.name = "test-water";
    w.c = {0.45, 0.19, 0.17};
    w.b = {0.11, 0.12, 0.13};
    w.phase.kind = PhaseKind::HenyeyGreenstein;
    w.phase.g = 0.9;
    return w;
}

/// An asset whose value at column (i, j), sample k is f(u, v, z) per channel.
inline Asset function_asset(const Camera& cam, int step, DepthScheme scheme, int K, double z_max,
                            const std::function<Rgb(double, double, double)>& f) {
    Asset a;
    a.info.camera = cam;
    a.info.rig = two_lamp_rig();
    a.info.water = test_water();
    a.info.lattice = make_lattice(cam, step, scheme, depth_samples(scheme, K, z_max));
    a.info.baker_version = "test";
    a.info.input_hash = "fnv1a64:0000000000000000";
    a.allocate();
    const Lattice& l = a.lattice();
    for (int i = 0; i < l.ni; ++i) {
        for (int j = 0; j < l.nj; ++j) {
            for (int k = 0; k < l.nk(); ++k) {
                const Rgb x = f(l.u(i), l.v(j), l.z[k]);
                float* p = a.values.data() + a.index(i, j, k);
                p[0] = float(x.r);
                p[1] = float(x.g);
                p[2] = float(x.b);
            }
        }
    }
    return a;
}

/// Smooth, positive, increasing in z, not linear in any variable.
inline Rgb smooth_field(double u, double v, double z) {
    const double g = std::exp(-((u - 30) * (u - 30) + (v - 20) * (v - 20)) / 2000.0);
    const double rise = 1.0 - std::exp(-0.7 * z);
    return Rgb{1e-3, 2e-3, 3e-3} * (g * rise + 0.1 * z);
}

}  // namespace deepsea::test
