#pragma once
/// \file Pinhole camera (DESIGN.md section 1).

#include "deepsea/core/vec.h"

namespace deepsea {

/// What a depth value measures along a pixel's ray.
enum class DepthKind {
    Z,      ///< planar depth: the z coordinate of the surface point (default)
    Range,  ///< distance from the camera centre along the ray
};

/// Pinhole intrinsics in pixels. Pixel (u, v), 0-based, has its centre at (u, v).
struct Camera {
    int width = 0;
    int height = 0;
    double fx = 0.0, fy = 0.0;
    double cx = 0.0, cy = 0.0;

    /// Unnormalised viewing ray r = ((u - cx)/fx, (v - cy)/fy, 1) of image point (u, v).
    Vec3 ray(double u, double v) const { return {(u - cx) / fx, (v - cy) / fy, 1.0}; }
    /// cos(phi) = 1/|r|, phi = angle between the ray and the optical axis.
    double cos_phi(double u, double v) const;
    /// Camera-frame point of pixel (u, v) at the given depth (z-depth or range).
    Vec3 point(double u, double v, double depth, DepthKind kind = DepthKind::Z) const;
    /// Planar z-depth of a depth value of either kind at pixel (u, v).
    double z_depth(double u, double v, double depth, DepthKind kind) const;

    /// Same field of view and principal point in relative terms (fx/width, cx/width, ...),
    /// to 1e-6: an asset for such a camera can be resampled to this one.
    bool same_view(const Camera& o) const;
    bool operator==(const Camera& o) const;
};

}  // namespace deepsea
