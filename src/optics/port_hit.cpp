#include "deepsea/optics/port_hit.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

SurfaceTaps surface_taps(const Image& inv, double u, double v) {
    SurfaceTaps t;
    const int W = inv.width, H = inv.height;
    u = std::clamp(u, 0.0, double(W - 1));
    v = std::clamp(v, 0.0, double(H - 1));
    const int x0 = std::min(int(u), std::max(W - 2, 0)), y0 = std::min(int(v), std::max(H - 2, 0));
    const int dx = x0 + 1 < W ? 1 : 0;
    const double fu = u - x0, fv = v - y0;
    const float* r0 = inv.row(y0) + x0;
    const float* r1 = inv.row(std::min(y0 + 1, H - 1)) + x0;
    const float s[4] = {r0[0], r0[dx], r1[0], r1[dx]};
    const float lo = std::min(std::min(s[0], s[1]), std::min(s[2], s[3]));
    const float hi = std::max(std::max(s[0], s[1]), std::max(s[2], s[3]));
    if (lo > 0.0f && hi - lo <= float(kDepthDiscontinuity) * lo) {
        const double w[4] = {(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv};
        t.count = 4;
        const int y1 = std::min(y0 + 1, H - 1);
        const int xs[4] = {x0, x0 + dx, x0, x0 + dx}, ys[4] = {y0, y0, y1, y1};
        for (int i = 0; i < 4; ++i) {
            t.x[i] = xs[i];
            t.y[i] = ys[i];
            t.w[i] = w[i];
            t.inv_z += w[i] * s[i];
        }
        return t;
    }
    const int xn = std::min(int(u + 0.5), W - 1), yn = std::min(int(v + 0.5), H - 1);
    const float sn = inv.at(xn, yn);
    if (!(sn > 0.0f)) return t;
    t.count = 1;
    t.x[0] = xn;
    t.y[0] = yn;
    t.w[0] = 1.0;
    t.inv_z = sn;
    return t;
}

namespace {

/// The ray at inverse depth s against the surface: h = s - 1 / z_surface, > 0 in front of it
/// (the surface is deeper), <= 0 on or behind it. Open water is in front at any s (`open`).
struct Probe {
    double s = 0.0, h = 0.0;
    bool open = false;
    SurfaceTaps taps;
    bool front() const { return open || h > 0.0; }
};

struct Marcher {
    const Image& inv;
    const RayProjection& ray;

    Probe at(double s) const {
        const SurfaceTaps t = surface_taps(inv, ray.u_inf + ray.du * s, ray.v_inf + ray.dv * s);
        return {s, s - t.inv_z, t.count == 0, t};
    }

    /// The crossing between a (in front) and b (behind, b.s < a.s): Illinois steps (bisection
    /// while a is open water, whose h says nothing of distance). Returns the crossing and
    /// whether the surface is continuous across it (not a depth edge).
    Probe refine(Probe a, Probe b, bool& continuous) const {
        const double rate = ray.rate();
        Probe best = b;
        int side = 0;
        continuous = false;
        for (int it = 0; it < 200 && b.h != 0.0; ++it) {
            double s = a.open ? 0.5 * (a.s + b.s) : (a.s * b.h - b.s * a.h) / (b.h - a.h);
            if (!(s < a.s && s > b.s)) s = 0.5 * (a.s + b.s);
            const Probe c = at(s);
            if (c.front()) {
                a = c;
                if (side == 1) b.h *= 0.5;
                side = 1;
            } else {
                b = c;
                if (side == -1 && !a.open) a.h *= 0.5;
                side = -1;
            }
            best = c;
            if (!c.open && std::fabs(c.h) <= kPortHitTolerance * (c.s + c.taps.inv_z)) {
                // on the surface, between four pixels of one surface: no edge here
                if (c.taps.count == 4) {
                    continuous = true;
                    return c;
                }
                break;
            }
            if ((a.s - b.s) * rate <= kPortHitTolerance || a.s - b.s <= 1e-15 * a.s) {
                best = b;
                break;
            }
        }
        if (b.h == 0.0) best = b;
        // Across the crossing, a thousandth of a pixel either way: one surface, or an edge.
        const double ds = std::min(1e-3 / rate, 1e-3 * best.s);
        const Probe n = at(best.s + ds), f = at(std::max(best.s - ds, 0.0));
        const double lo = std::min(n.taps.inv_z, f.taps.inv_z);
        const double hi = std::max(n.taps.inv_z, f.taps.inv_z);
        continuous = !n.open && !f.open && hi - lo <= kDepthDiscontinuity * lo;
        return best;
    }
};

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

bool sees_input(const Camera& input, const RayProjection& ray) {
    if (!ray.forward) return false;
    double lo = 0.0, hi = std::min(ray.s_origin, 1.0 / kPortViewNear);
    view_interval(ray.u_inf, ray.du, input.width, lo, hi);
    view_interval(ray.v_inf, ray.dv, input.height, lo, hi);
    return lo <= hi;
}

PortHit find_port_hit(const Camera& input, const Image& inv, const RayProjection& ray,
                      const Vec3& origin, const Vec3& direction, double z_near) {
    PortHit hit;
    if (!ray.forward) return hit;
    // Nothing is nearer than z_near (the march starts a little nearer, so that a surface at
    // exactly z_near is met by a crossing, not by rounding); the ray exists from its origin on.
    double lo = 0.0, hi = std::min(ray.s_origin, 1.001 / z_near);
    if (!(hi < HUGE_VAL)) hi = 1e3;  // (a ray from the camera plane: from 1 mm on)
    view_interval(ray.u_inf, ray.du, input.width, lo, hi);
    view_interval(ray.v_inf, ray.dv, input.height, lo, hi);
    if (!(lo <= hi)) return hit;  // never inside the input's view
    const Marcher m{inv, ray};
    const auto surface = [&](const Probe& p) {
        hit.kind = PortHitKind::Surface;
        hit.z = 1.0 / p.s;
        hit.t = (hit.z - origin.z) / direction.z;
        hit.u = ray.u_inf + ray.du * p.s;
        hit.v = ray.v_inf + ray.dv * p.s;
        hit.taps = p.taps;
        return hit;
    };
    Probe prev = m.at(hi);
    if (!prev.open && prev.h == 0.0) return surface(prev);
    if (!prev.front()) return hit;  // enters the view behind a surface
    const double span = hi - lo;
    const int steps = int(std::clamp(std::ceil(span * ray.rate()), 1.0, 65536.0));
    bool behind_edge = false;
    for (int i = 1; i <= steps; ++i) {
        const Probe cur = m.at(i == steps ? lo : hi - span * i / steps);
        if (prev.front() && !cur.front()) {
            bool continuous = false;
            const Probe x = m.refine(prev, cur, continuous);
            if (continuous) return surface(x);
            behind_edge = true;  // passes behind a foreground edge: look beyond it
        }
        prev = cur;
    }
    // No crossing: open water if the whole ray to its vanishing point was in view.
    if (!behind_edge && prev.front() && lo == 0.0) hit.kind = PortHitKind::OpenWater;
    return hit;
}

}  // namespace deepsea
