#pragma once
/// \file Where a water-side ray through the port meets the surface that a pinhole depth map
/// describes (docs/ports.md, "Where a refracted ray meets the scene"). The input RGB-D is a
/// pinhole view from the camera centre; a ray through a port starts on the port's outer surface
/// and runs in another direction, so its hit is found by marching its projection through the
/// depth image. Pure geometry on a depth image: the runtime and the tests share it.

#include "deepsea/core/image.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"

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

/// Which input pixels a fractional image position takes its values from (depth, colour,
/// normal): bilinear between the four pixel centres around it where all four are surfaces on
/// one surface (optics' same_surface, each pair), otherwise the nearest pixel alone (nothing is
/// mixed across a depth edge). Positions are clamped to the pixel centres' range (the half
/// pixel at each border takes the border's values).
struct SurfaceTaps {
    int count = 0;  ///< 4 (bilinear), 1 (nearest) or 0 (the nearest pixel is open water)
    int x[4] = {}, y[4] = {};
    double w[4] = {};    ///< weights, summing to 1
    double inv_z = 0.0;  ///< the interpolated inverse planar depth 1 / z (0: open water)
};

/// A planar depth image's inverse, 1 / z, with 0 for open water (has_surface): what the march
/// reads. Inverse depth is interpolated, not depth: 1 / z is affine in (u, v) on any plane, so a
/// plane is reproduced exactly between its pixels.
Image inverse_depth(const Image& depth);

/// The taps at (u, v) of an inverse depth image (inverse_depth). Four pixels are one surface
/// where their depths lie within kDepthDiscontinuity of each other:
/// (max - min) <= kDepthDiscontinuity min, in depth or, equivalently, in inverse depth.
SurfaceTaps surface_taps(const Image& inv_depth, double u, double v);

/// What a ray sees of the input.
enum class PortHitKind {
    Surface,    ///< it meets the depth map's surface
    OpenWater,  ///< its whole path lies inside the input's view, in front of every surface
    Unseen,     ///< the input does not show what it meets: it leaves the view (or enters it
                ///< behind a surface), or passes behind a foreground edge and finds nothing after
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
/// (so its depth to about 1e-9 relative), or, at a depth edge, to this many pixels.
inline constexpr double kPortHitTolerance = 1e-9;

/// The first crossing of the ray with the surface of `inv_depth` (the input's inverse planar
/// depth, inverse_depth; camera
/// `input`), searched at depths >= z_near (the frame's nearest surface: nothing is hit before
/// it; +inf or 0 when the frame has no surface). Marches the projection from the ray's start
/// (or z_near, whichever is deeper) toward the vanishing point in steps of at most one pixel,
/// comparing the ray's inverse depth s with the surface's (surface_taps), and refines the first
/// sign change by the Illinois method (regula falsi with halving; exact in one step on a plane,
/// where both sides are affine in s). A sign change across a depth edge (the ray passes behind a
/// foreground surface the pinhole does not see past) is skipped: the hit is on a surface found
/// beyond it, or the ray is Unseen. `origin` and `direction` as given to project_ray.
PortHit find_port_hit(const Camera& input, const Image& inv_depth, const RayProjection& ray,
                      const Vec3& origin, const Vec3& direction, double z_near);

}  // namespace deepsea
