#pragma once
/// \file Surface normals from a planar depth map (docs/model.md, "Direct signal").

#include <cmath>

#include "deepsea/core/image.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/vec3t.h"

namespace deepsea {

/// Relative depth jump |dz| / z above which two neighbours are on different surfaces.
inline constexpr double kDepthDiscontinuity = 0.05;

/// Depth (metres) from which on a value is a "nothing here" sentinel (Blender writes 1e10 for
/// background, some sensors 65504 or 1e6): no lamp light comes back from that far (exp(-c d)
/// underflows for any real water), and float geometry would overflow.
inline constexpr double kFarDepth = 1e6;

/// True where a depth value is a surface: > 0 and < kFarDepth. Anything else (NaN, inf, <= 0,
/// sentinels) is open water.
inline bool has_surface(double z) { return z > 0.0 && z < kFarDepth; }
/// The same test on a float, without widening it (kFarDepth is exact in float), so that row
/// loops compare whole vectors of floats.
inline bool has_surface(float z) { return z > 0.0f && z < float(kFarDepth); }
static_assert(double(float(kFarDepth)) == kFarDepth, "kFarDepth must be exact in float");

/// True where neighbour depth zn lies on the same surface as the centre depth zc (both > 0,
/// metres): |zn - zc| <= kDepthDiscontinuity zc. Central differences across a larger jump
/// would mix two surfaces.
template <class T>
inline bool same_surface(T zc, T zn) {
    using std::fabs;
    return fabs(zn - zc) <= T(kDepthDiscontinuity) * zc;
}

/// Camera-frame point (metres) at planar depth z on the ray r = (rx, ry, 1): r z.
template <class T>
inline Vec3T<T> back_project(T rx, T ry, T z) {
    return {rx * z, ry * z, z};
}

/// Unit normal of the surface whose tangents along the image's x and y axes are tu and tv
/// (differences of back-projected neighbours, any length), turned to face the camera: n . r <=
/// 0 for r the pixel's ray (or its point). Where the tangents are parallel or zero there is
/// no plane: the result is the zero vector (NaN for NaN tangents), and a caller that can meet
/// that tests dot(n, n) > 0 and picks a fallback. Templated for the same reasons as lamp.h:
/// the exact normals (double) and the runtime's vectorised rows (float) both call it.
template <class T>
inline Vec3T<T> normal_from_tangents(Vec3T<T> tu, Vec3T<T> tv, Vec3T<T> r) {
    using std::sqrt;
    const Vec3T<T> n = cross(tu, tv);
    const T len2 = dot(n, n);
    const T inv = len2 > T(0) ? T(1) / sqrt(len2) : T(0);
    return n * (dot(n, r) > T(0) ? -inv : inv);
}

/// Unit normal at pixel (u, v) of a one-channel planar z-depth map, facing the camera
/// (n . P < 0). Back-projects the pixel and its neighbours; central differences, one-sided
/// at borders, at open water and at depth discontinuities. Returns (0, 0, -1) where the
/// pixel has no surface or no usable neighbour.
Vec3 surface_normal(const Camera& cam, const Image& zdepth, int u, int v);

}  // namespace deepsea
