#pragma once
/// \file Pinhole camera (docs/model.md; OpenCV frame, pixel centres at integers), and what
/// follows from it alone: depth conversion and the camera of frames of another size.

#include <string>

#include "deepsea/core/image.h"
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

    /// Unnormalised viewing ray r = ((u - cx)/fx, (v - cy)/fy, 1) of image point (u, v): the
    /// pinhole's one equation, which every renderer and the baker use (ray_x, ray_y: its
    /// components, x / z and y / z of the points the pixel sees).
    Vec3 ray(double u, double v) const { return {ray_x(u), ray_y(v), 1.0}; }
    double ray_x(double u) const { return (u - cx) / fx; }
    double ray_y(double v) const { return (v - cy) / fy; }
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

/// "800x800 fx=600 fy=600 cx=400 cy=400": a camera in one line, for messages.
std::string describe(const Camera& camera);

/// Throws AssetError naming both cameras unless `frames` equals `baked` (the camera an asset
/// was baked for) or has the same view at another resolution (Camera::same_view).
void check_same_view(const Camera& baked, const Camera& frames);

/// The camera of width x height frames rendered with an asset baked for `baked`: `requested`
/// if set (width > 0), else `baked` scaled to the frame size (pixel edges scaled, so the rays
/// stay the same; AssetError if the aspect ratio differs). Then AssetError unless it has
/// `baked`'s view (check_same_view), InputError unless it is width x height.
Camera frame_camera(const Camera& baked, const Camera& requested, int width, int height);

/// Converts a one-channel depth map of the given kind to planar z-depth, in place. Open water
/// (no surface, see normals.h's has_surface) is kept as it is.
void to_planar_depth(const Camera& camera, Image& depth, DepthKind kind);

}  // namespace deepsea
