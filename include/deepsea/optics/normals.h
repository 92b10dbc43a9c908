#pragma once
/// \file Surface normals from a planar depth map.

#include "deepsea/core/image.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"

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

/// Unit normal at pixel (u, v) of a one-channel planar z-depth map, facing the camera
/// (n . P < 0). Back-projects the pixel and its neighbours; central differences, one-sided
/// at borders, at open water and at depth discontinuities. Returns (0, 0, -1) where the
/// pixel has no surface or no usable neighbour.
Vec3 surface_normal(const Camera& cam, const Image& zdepth, int u, int v);

}  // namespace deepsea
