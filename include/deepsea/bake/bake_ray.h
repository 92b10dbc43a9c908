#pragma once
/// \file The ray a lattice column (and the accuracy check's test pixel) integrates along
/// (docs/port-bake.md, "Baking through a port"): the pinhole ray from the camera centre, or through
/// a port the pixel's water-side ray (the green channel's), from the port's outer surface. Its
/// samples are indexed by the planar depth z of the point on the ray, so that the runtime looks
/// a port asset up with the hit's planar depth exactly as a pinhole one.

#include <algorithm>
#include <optional>

#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/port.h"

namespace deepsea {

struct BakeRay {
    Vec3 origin;           ///< m, camera frame: 0, or the point on the port's outer surface
    Vec3 dir;              ///< unit direction
    double stretch = 1.0;  ///< pinhole: |Camera::ray| = 1 / dir.z, t = z stretch
    bool port = false;

    /// Path length from the origin to planar depth z; 0 for a depth before the origin (inside
    /// the housing, where nothing scatters). Pinhole: z |ray| as the baker always computed it.
    double path(double z) const {
        return port ? std::max(0.0, (z - origin.z) / dir.z) : z * stretch;
    }
    /// Planar depth of the point at path length t.
    double depth(double t) const { return port ? origin.z + t * dir.z : t / stretch; }
};

/// The ray of image point (u, v) of `camera`, through `port` where there is one (trace_port,
/// the green channel's direction). ConfigError naming camera.port where the point has no
/// water-side ray, or one that does not run forward (w.z <= 0: planar depth cannot index it).
BakeRay bake_ray(const Camera& camera, const std::optional<Port>& port, double u, double v);

}  // namespace deepsea
