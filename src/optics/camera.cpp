#include "deepsea/optics/camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deepsea/core/error.h"
#include "deepsea/optics/normals.h"

namespace deepsea {

double Camera::cos_phi(double u, double v) const { return 1.0 / length(ray(u, v)); }

Vec3 Camera::point(double u, double v, double depth, DepthKind kind) const {
    const Vec3 r = ray(u, v);
    return kind == DepthKind::Z ? r * depth : r * (depth / length(r));
}

double Camera::z_depth(double u, double v, double depth, DepthKind kind) const {
    return kind == DepthKind::Z ? depth : depth * cos_phi(u, v);
}

namespace {
bool close(double a, double b) {
    return std::fabs(a - b) <= 1e-6 * std::max(std::fabs(a), std::fabs(b)) + 1e-12;
}
}  // namespace

bool Camera::same_view(const Camera& o) const {
    // Compare in units of the image size, with pixel edges (not centres) scaled: pixel
    // centres sit at integers, so the image spans [-0.5, width - 0.5].
    return close(fx / width, o.fx / o.width) && close(fy / height, o.fy / o.height) &&
           close((cx + 0.5) / width, (o.cx + 0.5) / o.width) &&
           close((cy + 0.5) / height, (o.cy + 0.5) / o.height);
}

bool Camera::operator==(const Camera& o) const {
    return width == o.width && height == o.height && close(fx, o.fx) && close(fy, o.fy) &&
           close(cx, o.cx) && close(cy, o.cy);
}

std::string describe(const Camera& c) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%dx%d fx=%.6g fy=%.6g cx=%.6g cy=%.6g", c.width, c.height, c.fx,
                  c.fy, c.cx, c.cy);
    return buf;
}

void check_same_view(const Camera& baked, const Camera& frames) {
    if (baked == frames || baked.same_view(frames)) return;
    throw AssetError("asset was baked for camera " + describe(baked) +
                     " but the frames come from camera " + describe(frames) +
                     " (a different view; re-bake for this camera)");
}

Camera frame_camera(const Camera& baked, const Camera& requested, int width, int height) {
    Camera cam = requested;
    if (cam.width == 0) {
        cam = baked;
        if (width != baked.width || height != baked.height) {
            const double sx = double(width) / baked.width, sy = double(height) / baked.height;
            if (std::fabs(sx - sy) > 1e-9 * sx) {
                // The same rays would need non-square pixels: almost surely another camera.
                throw AssetError("frames are " + std::to_string(width) + "x" +
                                 std::to_string(height) + " but the asset was baked for " +
                                 describe(baked) + " (another aspect ratio; pass the frames' " +
                                 "own camera if they really have that view)");
            }
            cam.width = width;
            cam.height = height;
            cam.fx = baked.fx * sx;
            cam.fy = baked.fy * sy;
            // pixel centres at integers: scale the pixel edges, not the centres
            cam.cx = (baked.cx + 0.5) * sx - 0.5;
            cam.cy = (baked.cy + 0.5) * sy - 0.5;
        }
    }
    check_same_view(baked, cam);
    if (cam.width != width || cam.height != height) {
        throw InputError("frames are " + std::to_string(width) + "x" + std::to_string(height) +
                         " but the camera is " + describe(cam));
    }
    return cam;
}

void to_planar_depth(const Camera& camera, Image& depth, DepthKind kind) {
    if (kind == DepthKind::Z) return;
    for (int v = 0; v < depth.height; ++v) {
        for (int u = 0; u < depth.width; ++u) {
            float& d = depth.at(u, v);
            if (has_surface(d)) d = float(camera.z_depth(u, v, d, kind));
        }
    }
}

}  // namespace deepsea
