#include "deepsea/optics/normals.h"

#include <cmath>

namespace deepsea {

namespace {

/// Pixel (u, v)'s point at planar depth z, through the shared back-projection.
Vec3T<double> point(const Camera& cam, int u, int v, double z) {
    const Vec3 r = cam.ray(u, v);
    return back_project(r.x, r.y, z);
}

/// Neighbour (u, v) usable for a difference with the centre depth zc: inside the image, a
/// surface, and not across a depth discontinuity.
bool usable(const Image& z, int u, int v, double zc) {
    if (u < 0 || v < 0 || u >= z.width || v >= z.height) return false;
    const double zn = z.at(u, v);
    return has_surface(zn) && same_surface(zc, zn);
}

/// Tangent along one image axis: central where both neighbours are usable, else one-sided.
bool tangent(const Camera& cam, const Image& z, int u, int v, int du, int dv,
             const Vec3T<double>& P, Vec3T<double>& t) {
    const double zc = z.at(u, v);
    const bool fwd = usable(z, u + du, v + dv, zc), back = usable(z, u - du, v - dv, zc);
    const auto pt = [&](int x, int y) { return point(cam, x, y, z.at(x, y)); };
    if (fwd && back) {
        t = pt(u + du, v + dv) - pt(u - du, v - dv);
    } else if (fwd) {
        t = pt(u + du, v + dv) - P;
    } else if (back) {
        t = P - pt(u - du, v - dv);
    } else {
        return false;
    }
    return true;
}

}  // namespace

Vec3 surface_normal(const Camera& cam, const Image& zdepth, int u, int v) {
    const double z = zdepth.at(u, v);
    if (!has_surface(z)) return {0.0, 0.0, -1.0};
    const Vec3T<double> P = point(cam, u, v, z);
    Vec3T<double> tu, tv;
    if (!tangent(cam, zdepth, u, v, 1, 0, P, tu) || !tangent(cam, zdepth, u, v, 0, 1, P, tv)) {
        return -normalize(vec3(P));  // an isolated pixel: assume it faces the camera
    }
    const Vec3T<double> n = normal_from_tangents(tu, tv, P);
    if (!(dot(n, n) > 0.0)) return -normalize(vec3(P));  // parallel tangents: no plane
    return vec3(n);
}

}  // namespace deepsea
