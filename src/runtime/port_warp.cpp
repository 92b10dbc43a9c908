// The port's rows (docs/ports.md, "Rendering through a port"): the input's passes, the hits'
// taps after the vectorised march (port_march_rows.cpp), and the rays it leaves to the scalar
// march. Compiled like the march (see port_lanes.h), so that its lanes give the same floats.

#include <algorithm>
#include <cmath>
#include <limits>

#include "clones.h"
#include "port_lanes.h"

namespace deepsea {

namespace port_lanes {

/// The Illinois step of the rays that fast_march bracketed (kActive), the same as the scalar
/// march's first, and the hits that it settles on one surface (kSurface): the point, the path
/// from the port, and the normal and colour from the four input pixels around the hit, with the
/// scalar code's arithmetic (port_row's; taps_at's weights). The step's probe reads its four
/// inverse depths from the interleaved surface (slot 3, beside the normal), which the normal's
/// and colour's taps load anyway: the same pixels, weights and sums as cell_probe, so the same
/// value without a gather of its own. Rays the step does not settle become kScalar; lanes
/// without a hit get zeros. Lane by lane the step's s and the taps' positions and weights, then
/// per pixel one 8-float load a tap (settle_taps), then lane by lane the step's outcome and the
/// normals' lengths.
/// Returns the number of rays left to the scalar march.
DEEPSEA_CLONES
int settle_hits(int n, const PortRays::MarchRow m, const Pinhole cam, const float* __restrict in,
                int W, int H, MarchScratch& f, const PortRow& o) {
    const float* __restrict as = f.as.data();
    const float* __restrict ah = f.ah.data();
    const float* __restrict bs = f.bs.data();
    const float* __restrict bh = f.bh.data();
    float* __restrict s_hit = f.s.data();
    int* __restrict state = f.state.data();
    int* __restrict at = f.steps.data();   // (spent by now)
    float* __restrict lo_z = f.ps.data();  // (likewise)
    float* __restrict hi_z = f.ph.data();  // (likewise)
    float* __restrict w = f.w.data();      // (the taps' weights, then their sums: 4 a pixel)
    float* __restrict x = o.x, * __restrict y = o.y, * __restrict z = o.z, * __restrict t = o.t;
    float* __restrict nx = o.nx, * __restrict ny = o.ny, * __restrict nz = o.nz;
    float* __restrict J = o.J, * __restrict mask = o.mask;
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const bool active = state[u] == kActive;
        float s = illinois_step(as[u], ah[u], bs[u], bh[u]);
        s = active ? s : 0.0f;  // (the vanishing point: its taps lie in PortRays::reach)
        s_hit[u] = s;
        float fu, fv;
        place_taps(m.u_inf[u] + m.du[u] * s, m.v_inf[u] + m.dv[u] * s, W, H, active, at[u],
                   w + 4 * u, fu, fv);
    }
    taps_row(n, in, at, std::size_t(W) * kPortSurfaceChannels, w, lo_z, hi_z, J);
    int left = 0;
#pragma omp simd reduction(+ : left)
    for (int u = 0; u < n; ++u) {
        const int st = state[u];
        const float s = s_hit[u];
        // on the surface, between four pixels of one surface: the scalar march's hit; any
        // other outcome of the step is left to it
        const bool hit = (st == kActive) & settles(lo_z[u], hi_z[u], s, w[4 * u + 3]);
        const int next = hit ? kSurface : st == kActive ? kScalar : st;
        state[u] = next;
        left += (next == kSurface) | (next == kOpen) | (next == kUnseen) ? 0 : 1;
        float xh, yh, zh, th;
        hit_point(m.u_inf[u] + m.du[u] * s, m.v_inf[u] + m.dv[u] * s, s, m.oz[u], m.dz[u], cam, xh,
                  yh, zh, th);
        x[u] = hit ? xh : 0.0f;
        y[u] = hit ? yh : 0.0f;
        z[u] = hit ? zh : 0.0f;
        t[u] = hit ? th : 0.0f;
        mask[u] = (hit | (st == kOpen)) ? 1.0f : 0.0f;
        unit_normal(w[4 * u], w[4 * u + 1], w[4 * u + 2], nx[u], ny[u], nz[u]);
    }
    return left;
}

}  // namespace port_lanes

using namespace port_lanes;

DEEPSEA_CLONES
float port_depth_row(int W, const float* __restrict z, float* __restrict inv,
                     float* __restrict window_row) {
    float near = std::numeric_limits<float>::infinity();
#pragma omp simd reduction(min : near)
    for (int u = 0; u < W; ++u) {
        inv[u] = z[u] > 0.0f ? 1.0f / z[u] : 0.0f;
        near = z[u] > 0.0f && z[u] < near ? z[u] : near;
    }
    window_row_maxima(inv, W, window_row);
    return near;
}

DEEPSEA_CLONES
void port_surface_row(int n, const float* __restrict nx, const float* __restrict ny,
                      const float* __restrict nz, const float* __restrict J,
                      const float* __restrict inv, float* __restrict surface) {
    for (int u = 0; u < n; ++u) {
        float* p = surface + std::size_t(u) * kPortSurfaceChannels;
        store4(p, Float4{nx[u], ny[u], nz[u], inv[u]});
        store4(p + 4, Float4{J[3 * u], J[3 * u + 1], J[3 * u + 2], 0.0f});
    }
}

void port_row(const PortRays& rays, int v, const Image& inv_depth, const Image& nearest,
              const Image& surface, double z_near, const PortRow& o) {
    const int W = rays.camera().width;
    const Pinhole cam(rays.camera());
    const float s_near = float(1.001 / z_near);
    const float* in = surface.data.data();
    thread_local MarchScratch scratch;
    MarchScratch& f = scratch;  // (one look-up of the thread's scratch, not one a pixel)
    f.fit(W);
    const bool fast = inv_depth.width >= 2 && inv_depth.height >= 2;
    int left = W;
    if (fast) {
        const PortRays::MarchRow m = rays.march_row(v, s_near);
        fast_march(W, m, inv_depth.data.data(), nearest.data.data(), inv_depth.width,
                   inv_depth.height, s_near, f);
        left = settle_hits(W, m, cam, in, inv_depth.width, inv_depth.height, f, o);
    }
    // The rest, one by one (rare: depth edges, open water, long marches), up to the last of them
    const int* state = f.state.data();
    for (int u = 0; u < W && left > 0; ++u) {
        const int st = fast ? state[u] : kScalar;
        if (st == kSurface || st == kOpen || st == kUnseen) continue;  // (done above)
        --left;
        // (kActive and kMarching too: not settled in the fast steps; the scalar march starts
        // again)
        const PortMarch<float> m = rays.march(u, v);
        float start = s_near;
        if (fast) {
            start = f.start[u];
        } else if (const int w = port_start_window(m, s_near, W, inv_depth.height); w >= 0) {
            start = port_start_s(s_near, nearest.data[w]);
        }
        const PortCrossing<float> h = march_port_ray(inv_depth, m, start);
        o.mask[u] = h.kind != PortHitKind::Unseen ? 1.0f : 0.0f;
        if (h.kind != PortHitKind::Surface) {
            o.x[u] = o.y[u] = o.z[u] = o.t[u] = 0.0f;
            o.nx[u] = o.ny[u] = o.nz[u] = 0.0f;
            o.J[3 * u] = o.J[3 * u + 1] = o.J[3 * u + 2] = 0.0f;
            continue;
        }
        const PortRays::Ray& r = rays.ray(u, v);
        // the point at the hit's planar depth on the ray (its z is the hit's z exactly)
        hit_point(m.u_inf + m.du * h.s, m.v_inf + m.dv * h.s, h.s, r.oz, r.dz, cam, o.x[u], o.y[u],
                  o.z[u], o.t[u]);
        const SurfaceTapsT<float>& taps = h.taps;
        Float4 n = splat(0.0f), j = splat(0.0f);
        for (int i = 0; i < taps.count; ++i) {
            const float* p = in + (std::size_t(taps.y[i]) * W + taps.x[i]) * kPortSurfaceChannels;
            n += splat(taps.w[i]) * load4(p);
            j += splat(taps.w[i]) * load4(p + 4);
        }
        unit_normal(n[0], n[1], n[2], o.nx[u], o.ny[u], o.nz[u]);
        for (int c = 0; c < 3; ++c) o.J[3 * u + c] = j[c];
    }
}

}  // namespace deepsea
