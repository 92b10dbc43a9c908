#include "port_warp.h"

#include <cmath>

#include "float4.h"

namespace deepsea {

void port_row(const PortRays& rays, int v, const Image& inv_depth, const Image& surface,
              double z_near, const PortRow& o) {
    const int W = rays.camera().width;
    const float s_near = float(1.001 / z_near);
    const float* in = surface.data.data();
    for (int u = 0; u < W; ++u) {
        const PortCrossing<float> h = march_port_ray(inv_depth, rays.march(u, v), s_near);
        o.mask[u] = h.kind != PortHitKind::Unseen ? 1.0f : 0.0f;
        if (h.kind != PortHitKind::Surface) {
            o.x[u] = o.y[u] = o.z[u] = o.t[u] = 0.0f;
            o.nx[u] = o.ny[u] = o.nz[u] = 0.0f;
            o.J[3 * u] = o.J[3 * u + 1] = o.J[3 * u + 2] = 0.0f;
            continue;
        }
        const PortRays::Ray& r = rays.ray(u, v);
        // the point at the hit's planar depth on the ray (its z is the hit's z exactly)
        const float z = 1.0f / h.s, t = (z - r.oz) / r.dz;
        o.x[u] = r.ox + t * r.dx;
        o.y[u] = r.oy + t * r.dy;
        o.z[u] = z;
        o.t[u] = t;
        const SurfaceTapsT<float>& taps = h.taps;
        Float4 n = splat(0.0f), j = splat(0.0f);
        for (int i = 0; i < taps.count; ++i) {
            const float* p = in + (std::size_t(taps.y[i]) * W + taps.x[i]) * kPortSurfaceChannels;
            n += splat(taps.w[i]) * load4(p);
            j += splat(taps.w[i]) * load4(p + 4);
        }
        const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const float inv = len > 0.0f ? 1.0f / len : 0.0f;
        o.nx[u] = n[0] * inv;
        o.ny[u] = n[1] * inv;
        o.nz[u] = n[2] * inv;
        for (int c = 0; c < 3; ++c) o.J[3 * u + c] = j[c];
    }
}

}  // namespace deepsea
