#pragma once
/// \file Where a water-side ray through the port meets the surface that a pinhole depth map
/// describes (docs/ports.md, "Where a refracted ray meets the scene"). The input RGB-D is a
/// pinhole view from the camera centre; a ray through a port starts on the port's outer surface
/// and runs in another direction, so its hit is found by marching its projection through the
/// depth image. Pure geometry on a depth image, templated on the number type: the runtime's rows
/// march in float (runtime/port_warp.cpp), find_port_hit in double, with the same code.

#include <algorithm>
#include <cmath>
#include <limits>

#include "deepsea/core/image.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/normals.h"
#include "deepsea/optics/port.h"

namespace deepsea {

/// A water-side ray X(t) = origin + t direction (camera frame, metres; direction unit) as the
/// input's pinhole sees it. With s = 1 / X.z (inverse planar depth) its projection is a straight
/// line traversed at a constant rate:
///   u'(s) = u_inf + du s,  v'(s) = v_inf + dv s,
/// (u_inf, v_inf) the vanishing point of the direction, (du, dv) = (fx a.x, fy a.y) with
/// a = origin - origin.z direction / direction.z (where the ray crosses the plane z = 0).
struct RayProjection {
    double u_inf = 0.0, v_inf = 0.0;  ///< pixels
    double du = 0.0, dv = 0.0;        ///< pixels x metres
    double s_origin = 0.0;            ///< 1 / origin.z: the ray exists for s <= s_origin (0: none)
    bool forward = false;  ///< direction.z > 0: the ray goes deeper (otherwise it sees nothing)
    /// Pixels the projection moves per unit of s (the larger of |du|, |dv|).
    double rate() const;
};

/// The projection of the ray from `origin` along unit `direction` in the input camera.
RayProjection project_ray(const Camera& input, const Vec3& origin, const Vec3& direction);

/// Planar depth from which on a ray must see the input for the port to be usable (metres): no
/// scene lies within a hand's breadth of the housing's window, so a ray that sees the input
/// only nearer than this (its first centimetres beside the pixel it leaves) sees nothing of it.
inline constexpr double kPortViewNear = 0.1;

/// True where some part of the ray at planar depths >= kPortViewNear (and beyond its origin)
/// projects inside the input image (pixel edges -0.5 .. width - 0.5): the input can show
/// something of what it meets.
bool sees_input(const Camera& input, const RayProjection& ray);

/// ConfigError naming camera.port unless some pixel's water-side ray (trace_port, the green
/// channel's) sees the input (sees_input; the input a pinhole view from the camera centre with
/// the camera's intrinsics): through such a port the image would hold nothing of the frame. The
/// port must have passed validate and check_port_view. Stops at the first pixel that sees.
void check_port_sees_input(const Port& port, const Camera& camera);

/// What the march needs of one ray, all of it fixed per ray (PortRays keeps it in float): the
/// projection, and the stretch of s in which it lies inside the input image (pixel edges -0.5 ..
/// width - 0.5, s >= 0; empty where s_lo > s_hi).
template <class T>
struct PortMarch {
    T u_inf = 0, v_inf = 0, du = 0, dv = 0;  ///< the projection (RayProjection)
    T s_origin = 0;                          ///< the ray exists for s <= s_origin (0: none)
    T s_lo = 1, s_hi = 0;                    ///< the view's stretch of s
    T rate = 0;                              ///< RayProjection::rate
};

/// A ray's march constants from its projection in `input`.
PortMarch<double> port_march(const Camera& input, const RayProjection& ray);

/// Which input pixels a fractional image position takes its values from (depth, colour,
/// normal): bilinear between the four pixel centres around it where all four are surfaces on
/// one surface (optics' same_surface, each pair), otherwise the nearest pixel alone (nothing is
/// mixed across a depth edge). Positions are clamped to the pixel centres' range (the half
/// pixel at each border takes the border's values).
template <class T>
struct SurfaceTapsT {
    int count = 0;  ///< 4 (bilinear), 1 (nearest) or 0 (the nearest pixel is open water)
    int x[4] = {}, y[4] = {};
    T w[4] = {};  ///< weights, summing to 1
    T inv_z = 0;  ///< the interpolated inverse planar depth 1 / z (0: open water)
};
using SurfaceTaps = SurfaceTapsT<double>;

/// A planar depth image's inverse, 1 / z, with 0 for open water (has_surface): what the march
/// reads. Inverse depth is interpolated, not depth: 1 / z is affine in (u, v) on any plane, so a
/// plane is reproduced exactly between its pixels.
Image inverse_depth(const Image& depth);

namespace port_detail {

/// surface_taps' rule at (u, v); returns the count and the inverse depth, and fills `taps`
/// (weights and pixels) only where kTaps: the march's probes need the value alone.
template <class T, bool kTaps>
inline int taps_at(const Image& inv, T u, T v, T& inv_z, SurfaceTapsT<T>* taps) {
    const int W = inv.width, H = inv.height;
    u = std::clamp(u, T(0), T(W - 1));
    v = std::clamp(v, T(0), T(H - 1));
    const int x0 = std::min(int(u), std::max(W - 2, 0)), y0 = std::min(int(v), std::max(H - 2, 0));
    const int dx = x0 + 1 < W ? 1 : 0, y1 = std::min(y0 + 1, H - 1);
    const float* r0 = inv.data.data() + std::size_t(y0) * W + x0;
    const float* r1 = inv.data.data() + std::size_t(y1) * W + x0;
    const float s0 = r0[0], s1 = r0[dx], s2 = r1[0], s3 = r1[dx];
    const float lo = std::min(std::min(s0, s1), std::min(s2, s3));
    const float hi = std::max(std::max(s0, s1), std::max(s2, s3));
    if (lo > 0.0f && hi - lo <= float(kDepthDiscontinuity) * lo) {
        const T fu = u - T(x0), fv = v - T(y0);
        const T w0 = (1 - fu) * (1 - fv), w1 = fu * (1 - fv), w2 = (1 - fu) * fv, w3 = fu * fv;
        inv_z = ((w0 * T(s0) + w1 * T(s1)) + w2 * T(s2)) + w3 * T(s3);
        if constexpr (kTaps) {
            const int xs[4] = {x0, x0 + dx, x0, x0 + dx}, ys[4] = {y0, y0, y1, y1};
            const T w[4] = {w0, w1, w2, w3};
            for (int i = 0; i < 4; ++i) {
                taps->x[i] = xs[i];
                taps->y[i] = ys[i];
                taps->w[i] = w[i];
            }
        }
        return 4;
    }
    const int xn = std::min(int(u + T(0.5)), W - 1), yn = std::min(int(v + T(0.5)), H - 1);
    const float sn = inv.data[std::size_t(yn) * W + xn];
    inv_z = sn > 0.0f ? T(sn) : T(0);
    if (!(sn > 0.0f)) return 0;
    if constexpr (kTaps) {
        taps->x[0] = xn;
        taps->y[0] = yn;
        taps->w[0] = 1;
    }
    return 1;
}

}  // namespace port_detail

/// The taps at (u, v) of an inverse depth image (inverse_depth). Four pixels are one surface
/// where their depths lie within kDepthDiscontinuity of each other:
/// (max - min) <= kDepthDiscontinuity min, in depth or, equivalently, in inverse depth.
template <class T>
inline SurfaceTapsT<T> surface_taps(const Image& inv, T u, T v) {
    SurfaceTapsT<T> t;
    t.count = port_detail::taps_at<T, true>(inv, u, v, t.inv_z, &t);
    return t;
}

/// What a ray sees of the input.
enum class PortHitKind {
    Surface,    ///< it meets the depth map's surface
    OpenWater,  ///< its whole path lies inside the input's view, in front of every surface
    Unseen,     ///< the input does not show what it meets: it leaves the view (or enters it
                ///< behind a surface), or passes behind a foreground edge and finds nothing after
};

/// A ray's hit in the number type of the march: the inverse planar depth s and the input image
/// position of the crossing, and the pixels there.
template <class T>
struct PortCrossing {
    PortHitKind kind = PortHitKind::Unseen;
    T s = 0, u = 0, v = 0;  ///< (Surface)
    SurfaceTapsT<T> taps;   ///< the input pixels at (u, v) (Surface)
};

/// A ray's hit: where on the input image, at what planar depth, how far along the ray.
struct PortHit {
    PortHitKind kind = PortHitKind::Unseen;
    double u = 0.0, v = 0.0;  ///< input image position of the hit (Surface)
    double z = 0.0;           ///< planar depth of the hit point, metres (Surface)
    double t = 0.0;           ///< path from the ray's origin to the hit, metres (Surface)
    SurfaceTaps taps;         ///< the input pixels at (u, v) (Surface)
    bool seen() const { return kind != PortHitKind::Unseen; }
};

/// Tolerance of the refinement: the crossing is located to this share of its inverse depth
/// (so its depth to about 1e-9 relative), or, at a depth edge, to this many pixels; in float,
/// kPortHitToleranceFloat (a few units in the last place).
inline constexpr double kPortHitTolerance = 1e-9;
inline constexpr float kPortHitToleranceFloat = 1e-6f;

/// Where the projection moves less than this many pixels over the whole march it is taken as
/// standing still (a dome with the camera at its centre: not at all): the hit is the surface
/// under it, without a march.
inline constexpr double kPortStillPx = 0.01;

/// The input is cut into blocks of kPortStartBlock x kPortStartBlock pixels (the last ones
/// cut short by the image's edge); a ray's window is the 3 x 3 blocks around one block.
inline constexpr int kPortStartBlock = 8;

/// Where the march of `ray` may start instead of s_near: every input pixel that the march from
/// min(s_near, s_hi) down to s_lo reads (the bilinear and nearest taps of its projection, and the
/// probes a thousandth of a pixel beyond it) lies in the window of 3 x 3 blocks around one block,
/// whose index (by bw + bx, bw = ceil(W / kPortStartBlock) blocks a row) this returns. Then no
/// surface the march reads is nearer than the window's nearest one, max_inv (its largest inverse
/// depth, 0 where it shows only open water): the ray is in front of the surface for every
/// s > max_inv, and port_start_s gives the march's start. -1 where the projection is too long
/// for one window (or the ray has no stretch in view): the march starts at s_near.
template <class T>
inline int port_start_window(T u_inf, T v_inf, T du, T dv, T s_lo, T s_hi, T s_near, int W, int H) {
    const T e = s_hi < s_near ? s_hi : s_near;
    T u0 = u_inf + du * s_lo, u1 = u_inf + du * e;
    T v0 = v_inf + dv * s_lo, v1 = v_inf + dv * e;
    const T wm = T(W - 1), hm = T(H - 1);
    u0 = u0 > 0 ? (u0 < wm ? u0 : wm) : T(0);
    u1 = u1 > 0 ? (u1 < wm ? u1 : wm) : T(0);
    v0 = v0 > 0 ? (v0 < hm ? v0 : hm) : T(0);
    v1 = v1 > 0 ? (v1 < hm ? v1 : hm) : T(0);
    const T ulo = u0 < u1 ? u0 : u1, uhi = u0 < u1 ? u1 : u0;
    const T vlo = v0 < v1 ? v0 : v1, vhi = v0 < v1 ? v1 : v0;
    const T B = T(kPortStartBlock);
    // (floor, not a plain conversion, which GCC does not vectorise; the positions are >= 0)
    const T bx = std::floor(T(0.5) * (ulo + uhi) / B), by = std::floor(T(0.5) * (vlo + vhi) / B);
    // (taps reach floor(x) + 1 on each side: a margin of one pixel below, two above; & not &&:
    // no branches, so that the compositor's rows vectorise it)
    const bool fits = (s_lo <= e) & (e < T(1e30)) & (ulo - 1 >= B * (bx - 1)) &
                      (uhi + 3 <= B * (bx + 2)) & (vlo - 1 >= B * (by - 1)) &
                      (vhi + 3 <= B * (by + 2));
    const int bw = (W + kPortStartBlock - 1) / kPortStartBlock;
    return fits ? int(by) * bw + int(bx) : -1;
}
template <class T>
inline int port_start_window(const PortMarch<T>& ray, T s_near, int W, int H) {
    return port_start_window(ray.u_inf, ray.v_inf, ray.du, ray.dv, ray.s_lo, ray.s_hi, s_near, W,
                             H);
}

/// The march's start from the window's nearest surface max_inv (port_start_window): a thousandth
/// in front of it, never beyond s_near.
template <class T>
inline T port_start_s(T s_near, T max_inv) {
    const T s = max_inv * T(1.001);
    return s < s_near ? s : s_near;
}

/// The first crossing of a ray with the surface of `inv` (the input's inverse planar depth,
/// inverse_depth), searched at inverse depths s <= s_near (1.001 / z_near, z_near the frame's
/// nearest surface: nothing is hit before it; 0 when the frame has no surface). Marches the
/// projection from the ray's start (or s_near, whichever is deeper) toward the vanishing point in
/// steps of at most one pixel, comparing the ray's s with the surface's (surface_taps), and
/// refines the first sign change by the Illinois method (regula falsi with halving; exact in one
/// step on a plane, where both sides are affine in s). A sign change across a depth edge (the ray
/// passes behind a foreground surface the pinhole does not see past) is skipped: the hit is on a
/// surface found beyond it, or the ray is Unseen. Defined in port_march.h.
template <class T>
PortCrossing<T> march_port_ray(const Image& inv, const PortMarch<T>& ray, T s_near);

/// The same in double for the ray from `origin` along unit `direction` (project_ray's), with
/// its planar depth and path length; z_near as above in metres (+inf or 0 without a surface).
PortHit find_port_hit(const Camera& input, const Image& inv_depth, const RayProjection& ray,
                      const Vec3& origin, const Vec3& direction, double z_near);

}  // namespace deepsea

#include "deepsea/optics/port_march.h"
