#include "deepsea/optics/port_hit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deepsea/core/error.h"
#include "deepsea/optics/normals.h"

namespace deepsea {

double RayProjection::rate() const { return std::max(std::fabs(du), std::fabs(dv)); }

RayProjection project_ray(const Camera& cam, const Vec3& o, const Vec3& d) {
    RayProjection p;
    p.forward = d.z > 0.0;
    if (!p.forward) return p;
    p.u_inf = cam.cx + cam.fx * d.x / d.z;
    p.v_inf = cam.cy + cam.fy * d.y / d.z;
    // where the ray's line crosses z = 0: X.x / X.z = d.x / d.z + a.x / X.z
    const double k = o.z / d.z;
    p.du = cam.fx * (o.x - k * d.x);
    p.dv = cam.fy * (o.y - k * d.y);
    p.s_origin = o.z > 0.0 ? 1.0 / o.z : std::numeric_limits<double>::infinity();
    return p;
}

Image inverse_depth(const Image& depth) {
    Image inv(depth.width, depth.height, 1);
    for (std::size_t i = 0; i < depth.data.size(); ++i) {
        const float z = depth.data[i];
        inv.data[i] = has_surface(z) ? 1.0f / z : 0.0f;
    }
    return inv;
}

namespace {

/// [lo, hi] of s where x_inf + dx s lies within [-0.5, n - 0.5]; empty (lo > hi) if nowhere.
void view_interval(double x_inf, double dx, int n, double& lo, double& hi) {
    const double a = -0.5, b = n - 0.5;
    if (dx == 0.0) {
        if (x_inf < a || x_inf > b) lo = HUGE_VAL, hi = -HUGE_VAL;
        return;
    }
    double s0 = (a - x_inf) / dx, s1 = (b - x_inf) / dx;
    if (s0 > s1) std::swap(s0, s1);
    lo = std::max(lo, s0);
    hi = std::min(hi, s1);
}

}  // namespace

PortMarch<double> port_march(const Camera& input, const RayProjection& ray) {
    PortMarch<double> m;
    if (!ray.forward) return m;
    m.u_inf = ray.u_inf;
    m.v_inf = ray.v_inf;
    m.du = ray.du;
    m.dv = ray.dv;
    m.s_origin = ray.s_origin;
    m.rate = ray.rate();
    double lo = 0.0, hi = std::numeric_limits<double>::infinity();
    view_interval(ray.u_inf, ray.du, input.width, lo, hi);
    view_interval(ray.v_inf, ray.dv, input.height, lo, hi);
    m.s_lo = lo;
    m.s_hi = hi;
    return m;
}

bool sees_input(const Camera& input, const RayProjection& ray) {
    if (!ray.forward) return false;
    const PortMarch<double> m = port_march(input, ray);
    return std::max(m.s_lo, 0.0) <= std::min({m.s_hi, ray.s_origin, 1.0 / kPortViewNear});
}

void check_port_sees_input(const Port& port, const Camera& camera) {
    const auto sees = [&](int u, int v) {
        const PortRay r = trace_port(port, camera, u, v);
        return r.valid() && sees_input(camera, project_ray(camera, r.origin, r.direction[1]));
    };
    // the centre first: nearly every port sees the input there
    if (sees(camera.width / 2, camera.height / 2)) return;
    for (int v = 0; v < camera.height; ++v)
        for (int u = 0; u < camera.width; ++u)
            if (sees(u, v)) return;
    throw ConfigError(
        "camera.port: no pixel's water-side ray sees the input's view (the RGB-D frame, a "
        "pinhole view from the camera centre with the same intrinsics): the image would hold "
        "nothing of the frame; check the port's normal, centre and indices");
}

PortHit find_port_hit(const Camera& input, const Image& inv, const RayProjection& ray,
                      const Vec3& origin, const Vec3& direction, double z_near) {
    const PortCrossing<double> c = march_port_ray(inv, port_march(input, ray), 1.001 / z_near);
    PortHit hit;
    hit.kind = c.kind;
    if (c.kind != PortHitKind::Surface) return hit;
    hit.z = 1.0 / c.s;
    hit.t = (hit.z - origin.z) / direction.z;
    hit.u = c.u;
    hit.v = c.v;
    hit.taps = c.taps;
    return hit;
}

}  // namespace deepsea
