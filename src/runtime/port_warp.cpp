#include "port_warp.h"

#include <cmath>

namespace deepsea {

void port_row(const PortRays& rays, int v, const Image& inv_depth, const Image& normals,
              const Image& color, double z_near, const PortRow& o) {
    const int W = rays.camera().width;
    for (int u = 0; u < W; ++u) {
        const PortHit h = rays.hit(u, v, inv_depth, z_near);
        o.mask[u] = h.seen() ? 1.0f : 0.0f;
        if (h.kind != PortHitKind::Surface) {
            o.x[u] = o.y[u] = o.z[u] = o.t[u] = 0.0f;
            o.nx[u] = o.ny[u] = o.nz[u] = 0.0f;
            o.J[3 * u] = o.J[3 * u + 1] = o.J[3 * u + 2] = 0.0f;
            continue;
        }
        const PortRays::Ray& r = rays.ray(u, v);
        // the point at the hit's planar depth on the ray (its z is the hit's z exactly)
        o.x[u] = float(double(r.ox) + h.t * double(r.dx));
        o.y[u] = float(double(r.oy) + h.t * double(r.dy));
        o.z[u] = float(h.z);
        o.t[u] = float(h.t);
        const SurfaceTaps& taps = h.taps;
        double n[3] = {0, 0, 0}, j[3] = {0, 0, 0};
        for (int i = 0; i < taps.count; ++i) {
            for (int c = 0; c < 3; ++c) {
                n[c] += taps.w[i] * normals.at(taps.x[i], taps.y[i], c);
                j[c] += taps.w[i] * color.at(taps.x[i], taps.y[i], c);
            }
        }
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const double inv = len > 0.0 ? 1.0 / len : 0.0;
        o.nx[u] = float(n[0] * inv);
        o.ny[u] = float(n[1] * inv);
        o.nz[u] = float(n[2] * inv);
        for (int c = 0; c < 3; ++c) o.J[3 * u + c] = float(j[c]);
    }
}

}  // namespace deepsea
