#pragma once
/// \file The lean of the camera-side forward scatter on a surface tilted to the ray
/// (docs/forward-lean.md). The transport table holds what a ray gathers from a plane facing it. A
/// source seen psi away on a plane tilted by alpha is counted there by the paths that cross the
/// tilted plane, not the facing one: per unit of image solid angle they number (cos(alpha) + beta_n
/// sin(alpha)) / (cos(alpha) + psi_n sin(alpha)) times as many, beta the paths' direction where
/// they arrive and _n the component towards the surface's near side. With beta = rho psi on
/// average,
///     K_tilted(psi) = K(psi) (1 + (rho - 1) tan(alpha) psi_n),
/// and tan(alpha) psi_n = -(ln r(q) - ln r(p)) to first order, r the surface's range along the
/// rays. rho = 3/2 both for one scattering uniformly along the ray (psi = theta (r - t) / r,
/// beta = theta) and for small-angle diffusion (E[x beta] / E[x^2 / r] = (L^2 / 2) / (L^2 / 3)).
/// The range seen from each pixel is the source's own (the table is read at it), so the lean
/// carries only the crossing, not the shorter path.

#include <algorithm>
#include <cmath>

namespace deepsea {

/// rho: the mean arrival direction of scattered light over its angle from the ray.
inline constexpr float kForwardLeanRho = 1.5f;
/// The largest tan(alpha) the lean takes (63 degrees): the factor above is first order, and at
/// grazing incidence the range's gradient has no bound.
inline constexpr float kForwardLeanMaxTilt = 2.0f;

/// The forward kernel's lean at a pixel, 1/px: a source du, dv pixels away weighs
/// 1 + lu du + lv dv times what the facing plane's kernel gives it, lu, lv = -(rho - 1) times
/// the gradient of ln(range) over the image. x, y: the ray (x, y, 1) of the pixel, (u - cx) /
/// fx and (v - cy) / fy; n: the surface normal (either sign, any length; 0: no surface, no
/// lean); fx, fy: pixels per unit of x, y.
inline void forward_lean(float x, float y, float nx, float ny, float nz, float fx, float fy,
                         float& lu, float& lv) {
    const float nn = nx * nx + ny * ny + nz * nz;
    if (!(nn > 0.0f)) {
        lu = lv = 0.0f;
        return;
    }
    const float vn = x * nx + y * ny + nz;
    const float v2 = x * x + y * y + 1.0f;
    // d ln r / dx = x / |v|^2 - n_x / (v . n) (r = |v| (P . n) / (v . n)), the same for y; its
    // length is about tan(alpha), held at kForwardLeanMaxTilt below (v . n floored so that a
    // surface seen edge-on gives no infinity: the hold takes it from there)
    const float t = std::sqrt(nx * nx + ny * ny);
    const float floor = t / (4.0f * kForwardLeanMaxTilt * std::sqrt(v2));
    const float den = vn < 0.0f ? std::min(vn, -floor) : std::max(vn, floor);
    const float gx = x / v2 - nx / den;
    const float gy = y / v2 - ny / den;
    const float g = std::sqrt(gx * gx + gy * gy);
    const float scale = g > kForwardLeanMaxTilt ? kForwardLeanMaxTilt / g : 1.0f;
    lu = -(kForwardLeanRho - 1.0f) * scale * gx / fx;
    lv = -(kForwardLeanRho - 1.0f) * scale * gy / fy;
}

}  // namespace deepsea
