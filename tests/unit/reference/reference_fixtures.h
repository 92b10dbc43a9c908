#pragma once
// Shared fixtures of the path tracer's tests: small cameras, rigs, planes, bins.

#include <algorithm>
#include <cmath>
#include <limits>

#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"

namespace deepsea::testing {

/// w x h pixels with a 64 degree horizontal field of view, centred.
inline Camera camera(int w, int h) {
    const double f = 0.5 * w / std::tan(0.5 * 64.0 * M_PI / 180.0);
    return Camera{w, h, f, f, 0.5 * (w - 1), 0.5 * (h - 1)};
}

/// volumes/demo.yaml's rig: lamps at x = -/+0.5 m toed in by 30.7 degrees, sigma 35 degrees.
inline Rig two_spots() {
    Rig rig;
    rig.name = "two-spots";
    for (int s : {-1, 1}) {
        Light l;
        l.position = {0.5 * s, 0.0, 0.0};
        const double a = 30.7 * M_PI / 180.0;
        l.direction = {-s * std::sin(a), 0.0, std::cos(a)};
        l.intensity = s < 0 ? Rgb(1.0, 0.9, 0.8) : Rgb(0.8, 0.9, 1.0);
        rig.lights.push_back(l);
    }
    return rig;
}

inline Water hg_water(Rgb c, Rgb b, double g) {
    Water w;
    w.name = "test";
    w.c = c;
    w.b = b;
    w.phase.kind = g == 0.0 ? PhaseKind::Isotropic : PhaseKind::HenyeyGreenstein;
    w.phase.g = g;
    return w;
}

/// Albedo and planar depth of a plane through (0, 0, z0) with normal along (nx, ny, -1), or of
/// open water (z0 <= 0); a checker albedo so that misplaced pixels would show.
struct Scene {
    Image rgb, depth;
};
inline Scene plane(const Camera& cam, double z0, double nx = 0.0, double ny = 0.0) {
    Scene s{Image(cam.width, cam.height, 3), Image(cam.width, cam.height, 1)};
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const Vec3 r = cam.ray(u, v);
            // n . (r z - p0) = 0 with n = (nx, ny, -1), p0 = (0, 0, z0)
            s.depth.at(u, v) = z0 > 0.0 ? float(-z0 / (nx * r.x + ny * r.y - 1.0))
                                        : std::numeric_limits<float>::infinity();
            const bool odd = (u / 4 + v / 4) % 2;
            s.rgb.at(u, v, 0) = odd ? 0.7f : 0.5f;
            s.rgb.at(u, v, 1) = 0.55f;
            s.rgb.at(u, v, 2) = odd ? 0.4f : 0.3f;
        }
    }
    return s;
}

/// Sum over the bin of b x b pixels at bin (i, j) of channel ch; with squared values (`sq`,
/// for standard errors: independent pixels' variances add).
inline double bin_sum(const Image& img, int i, int j, int ch, int b, bool sq = false) {
    double s = 0.0;
    for (int v = j * b; v < std::min((j + 1) * b, img.height); ++v) {
        for (int u = i * b; u < std::min((i + 1) * b, img.width); ++u) {
            const double x = img.at(u, v, ch);
            s += sq ? x * x : x;
        }
    }
    return s;
}

}  // namespace deepsea::testing
