#pragma once
/// \file The surface that the path tracer's scattered rays meet (private to the reference): the
/// depth map's surface where it is one plane, extended beyond the frame, or no surface at all.
/// Camera rays meet the pixel's own depth exactly (path_tracer.cpp); this is for every other
/// ray.

#include "deepsea/core/image.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"

namespace deepsea::detail {

/// Where a ray meets the surface.
struct SurfaceHit {
    double t = 0.0;      ///< distance along the ray, metres
    Vec3 P;              ///< the point, camera frame
    Rgb albedo;          ///< linear albedo there (0 on the back side)
    bool front = false;  ///< hit from the camera's side (the back side absorbs)
};

/// Open water (every pixel), or the plane through every surface pixel: the whole plane n . X =
/// offset in front of the camera centre (z > 0), so that light may leave it and come back
/// beyond the frame as it would from an infinite plane. Its albedo beyond the frame is the
/// nearest border pixel's (the frame's edges continued). Any other depth map is refused: a
/// general depth-map surface (a heightfield of pixel patches) is not implemented yet.
class SceneSurface {
public:
    /// InputError naming a pixel off the plane, or an open-water pixel whose ray meets it.
    SceneSurface(const Camera& camera, const Image& rgb, const Image& zdepth);

    bool empty() const { return !m_plane; }
    /// Unit normal facing the camera (n . X < offset on the camera's side); zero when empty.
    const Vec3& normal() const { return m_n; }
    /// The first hit at distance in (0, t_max) along unit direction d from O, if any. A ray that
    /// leaves the surface (`leaving`: O was a hit) cannot meet a plane again.
    bool hit(const Vec3& O, const Vec3& d, double t_max, SurfaceHit& out,
             bool leaving = false) const;
    /// O moved onto the surface along its normal (a depth map's point lies on the plane only
    /// to its precision; a path that leaves it must start on it). O itself when empty.
    Vec3 project(const Vec3& O) const;
    /// True where the segment from A to B crosses the surface (a point on it does not count).
    bool blocks(const Vec3& A, const Vec3& B) const;

private:
    Rgb albedo_at(const Vec3& P) const;

    const Camera& m_cam;
    const Image& m_rgb;
    bool m_plane = false;
    Vec3 m_n;
    double m_offset = 0.0;
};

}  // namespace deepsea::detail
