#include "deepsea/optics/camera.h"

#include <cmath>

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
bool close(double a, double b) { return std::fabs(a - b) <= 1e-6 * std::max(std::fabs(a), std::fabs(b)) + 1e-12; }
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

}  // namespace deepsea
