#pragma once
// Shared fixtures of the runtime tests: a small camera, a two-lamp rig, waters, planar scenes.

#include <cmath>
#include <limits>
#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/forward_transport.h"
#include "deepsea/optics/jerlov.h"
#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/forward_psf_blur.h"

namespace deepsea::testing {

inline Camera small_camera() { return Camera{120, 90, 90.0, 90.0, 59.5, 44.5}; }

/// The authors' test-set rig: lamps at x = -/+0.5 m yawed 0.536 rad inward.
inline Rig two_lamps() {
    Rig rig;
    rig.name = "two";
    for (int s : {-1, 1}) {
        Light l;
        l.position = {0.5 * s, 0.0, 0.0};
        l.direction = normalize(Vec3(-s * std::sin(0.536), 0.0, std::cos(0.536)));
        l.intensity = {1.0, 0.9, 0.8};
        rig.lights.push_back(l);
    }
    return rig;
}

inline Water ib_with_forward() {
    Water w = jerlov_water("IB");
    w.forward = default_forward_scatter(w);
    w.forward.enabled = true;
    return w;
}

/// A water of beam attenuation c and scattering b (1/m) with a Henyey-Greenstein phase
/// function of asymmetry g, forward scatter from the phase function.
inline Water hg_water(const Rgb& c, const Rgb& b, double g) {
    Water w;
    w.c = c;
    w.b = b;
    w.phase = {PhaseKind::HenyeyGreenstein, g};
    w.forward = phase_function_forward_scatter();
    return w;
}

/// validate.py's turbid water (c about 1, b about 0.8, HG 0.85): the forward-scatter tests'
/// scene beyond the frame.
inline Water turbid_water() { return hg_water(Rgb(1.0, 0.95, 1.05), Rgb(0.8, 0.78, 0.82), 0.85); }

/// turbid_water()'s transport table (8192 paths, depths to 4 m), blurred for a W x H frame at
/// fx px a radian: the forward-scatter tests' blur.
inline ForwardPsfBlur turbid_blur(double fx, int W, int H) {
    ForwardTransportSettings s;
    s.paths = 1 << 13;
    const Water w = turbid_water();
    return ForwardPsfBlur(
        ForwardPsf(trace_forward_psf(w, forward_psf_depths(4.0, 16), s), w, fx, W, H), w.c);
}

/// A tilted plane z = z0 + a x with a step onto a nearer box in one corner, a patch of open
/// water (NaN, inf, negative, zero), and an albedo pattern.
struct PlaneScene {
    Image rgb, depth;
};

inline PlaneScene plane_scene(const Camera& cam, double z0 = 3.0, double a = 0.3) {
    PlaneScene s{Image(cam.width, cam.height, 3), Image(cam.width, cam.height, 1)};
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const Vec3 r = cam.ray(u, v);
            float z = float(z0 / (1.0 - a * r.x));
            if (u < cam.width / 4 && v < cam.height / 4) z = float(z0 * 0.6);  // a box: a step
            s.depth.at(u, v) = z;
            s.rgb.at(u, v, 0) = 0.2f + 0.3f * float((u / 8 + v / 8) % 2);
            s.rgb.at(u, v, 1) = 0.35f;
            s.rgb.at(u, v, 2) = 0.25f + 0.002f * float(u);
        }
    }
    // open water in the bottom-right corner, every flavour of "no surface"
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                         std::numeric_limits<float>::infinity(), -1.0f, 0.0f};
    for (int v = cam.height - 12; v < cam.height; ++v) {
        for (int u = cam.width - 16; u < cam.width; ++u) s.depth.at(u, v) = bad[(u + v) % 4];
    }
    return s;
}

/// True if pixel (u, v) is within 1 px of a depth discontinuity or of open water.
inline bool near_edge(const Image& depth, int u, int v) {
    const float z = depth.at(u, v);
    for (int dv = -1; dv <= 1; ++dv) {
        for (int du = -1; du <= 1; ++du) {
            const int x = u + du, y = v + dv;
            if (x < 0 || y < 0 || x >= depth.width || y >= depth.height) continue;
            const float n = depth.at(x, y);
            if (!(n > 0.0f && n < 1e30f) || !(z > 0.0f && z < 1e30f)) return true;
            if (std::fabs(n - z) > 0.05f * z) return true;
        }
    }
    return false;
}

/// A lamp table on the default grid filled with a smooth field (decaying with distance,
/// brighter along the axis, coming mostly from the lamp; symmetric on the axis as a real
/// field is): for tests of interpolation, where a Monte Carlo table's node noise would measure
/// the table instead.
inline LampField smooth_lamp_field() {
    LampField smooth;
    smooth.nr = 40;
    smooth.ntheta = 37;
    smooth.r0 = 0.02;
    smooth.r_max = 15.0;
    smooth.sh.resize(smooth.size());
    for (int i = 0; i < smooth.nr; ++i) {
        const double r =
            smooth.r0 * std::pow(smooth.r_max / smooth.r0, double(i) / (smooth.nr - 1));
        for (int j = 0; j < smooth.ntheta; ++j) {
            const double th = M_PI * j / (smooth.ntheta - 1);
            const double base = std::exp(-0.6 * r) / (0.2 + r) * (1.2 + std::cos(th));
            // light arriving from the lamp's side: -x (toward the axis) and -z (from the
            // lamp); on the axis only the terms symmetric about it (m = 0) survive, as a real
            // field's must: m = +-1 terms go as sin(theta), m = +-2 as sin^2(theta)
            const double st = std::sin(th);
            const double coef[kShCount] = {1.0, 0.0,      -0.5 * std::cos(th), -0.5 * st, 0.0, 0.0,
                                           0.2, 0.1 * st, 0.05 * st * st};
            for (int m = 0; m < kShCount; ++m)
                for (int c = 0; c < 3; ++c)
                    smooth.sh[((i * smooth.ntheta + j) * kShCount + m) * 3 + c] =
                        float(base * coef[m] * (1.0 - 0.1 * c));
        }
    }
    return smooth;
}

/// The rows' definition of the lamps' scattered light at P with normal N, channel c: each
/// lamp's quadratic form (optics' lamp_field_quadratic, camera frame) times its intensity,
/// summed, evaluated at N, clamped at 0. In double.
inline double exact_scattered(const Rig& rig, const std::vector<LampField>& fields, const Vec3& P,
                              const Vec3& N, int c) {
    double q[3 * kQuadraticCount] = {}, ql[3 * kQuadraticCount];
    for (std::size_t l = 0; l < rig.lights.size(); ++l) {
        const Light& L = rig.lights[l];
        Vec3 ex, ey;
        lamp_frame(L.direction, ex, ey);
        const Vec3 p = P - L.position;
        const Vec3& a = L.direction;
        lamp_field_quadratic(LampFieldView<double>(fields[l]), ex.x, ex.y, ex.z, ey.x, ey.y, ey.z,
                             a.x, a.y, a.z, dot(p, ex), dot(p, ey), dot(p, a), ql, 1);
        for (int i = 0; i < 3 * kQuadraticCount; ++i)
            q[i] += L.intensity[i / kQuadraticCount] * ql[i];
    }
    return std::max(0.0, quadratic_irradiance(q + c * kQuadraticCount, 1, N.x, N.y, N.z));
}

}  // namespace deepsea::testing
