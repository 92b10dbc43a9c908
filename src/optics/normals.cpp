#include "deepsea/optics/normals.h"

#include <cmath>

namespace deepsea {

namespace {

/// Neighbour (u, v) usable for a difference with the centre depth zc: inside the image, a
/// surface, and not across a depth discontinuity.
bool usable(const Image& z, int u, int v, double zc) {
    if (u < 0 || v < 0 || u >= z.width || v >= z.height) return false;
    const double zn = z.at(u, v);
    return has_surface(zn) && std::fabs(zn - zc) <= kDepthDiscontinuity * zc;
}

/// Tangent along one image axis: central where both neighbours are usable, else one-sided.
bool tangent(const Camera& cam, const Image& z, int u, int v, int du, int dv, const Vec3& P,
             Vec3& t) {
    const double zc = z.at(u, v);
    const bool fwd = usable(z, u + du, v + dv, zc), back = usable(z, u - du, v - dv, zc);
    const auto pt = [&](int x, int y) { return cam.point(x, y, z.at(x, y)); };
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
    const Vec3 P = cam.point(u, v, z);
    Vec3 tu, tv;
    if (!tangent(cam, zdepth, u, v, 1, 0, P, tu) || !tangent(cam, zdepth, u, v, 0, 1, P, tv)) {
        return -normalize(P);  // an isolated pixel: assume it faces the camera
    }
    Vec3 n = cross(tu, tv);
    const double len = length(n);
    if (!(len > 0.0)) return -normalize(P);
    n = n / len;
    return dot(n, P) > 0.0 ? -n : n;
}

}  // namespace deepsea
