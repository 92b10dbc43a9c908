// The march's common case vectorised across a row: compiled with -fopenmp-simd,
// -ffp-contract=off and -fno-trapping-math (see CMakeLists.txt), not fast-math, so that its
// lanes do the scalar march's float arithmetic exactly and give the same hits.

#include "port_warp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "clones.h"
#include "float4.h"

namespace deepsea {

namespace {

/// What the vectorised march found for a ray.
enum FastState : int {
    kActive = 0,    ///< bracketed, refining
    kSurface = 1,   ///< the crossing at s, on one surface (as the scalar march's continuous hit)
    kScalar = 2,    ///< anything else: the scalar march (march_port_ray) decides
    kOpen = 3,      ///< in front of the surface over its whole view, to its vanishing point
    kUnseen = 4,    ///< in front over its whole view, which ends before the vanishing point
    kMarching = 5,  ///< in front of the surface so far, stepping toward the vanishing point
};

/// The steps of at most a pixel, and the Illinois steps after them, tried across the row before
/// a ray is left to the scalar march.
constexpr int kFastMarchSteps = 8;
constexpr int kFastSteps = 1;

/// port_detail::taps_at's value where its four pixels are one surface (the same arithmetic on
/// the same clamped position; W, H >= 2); `one` is 0 where taps_at would take the nearest pixel
/// or open water. NaN positions read pixel 0 (the ray is then left to the scalar march).
inline float probe4(const float* __restrict inv, int W, int H, float u, float v, float& one) {
    u = u > 0.0f ? u : 0.0f;
    u = u < float(W - 1) ? u : float(W - 1);
    v = v > 0.0f ? v : 0.0f;
    v = v < float(H - 1) ? v : float(H - 1);
    const int x0 = std::min(int(u), W - 2), y0 = std::min(int(v), H - 2);
    const int i = y0 * W + x0;
    const float s0 = inv[i], s1 = inv[i + 1], s2 = inv[i + W], s3 = inv[i + W + 1];
    const float lo = std::min(std::min(s0, s1), std::min(s2, s3));
    const float hi = std::max(std::max(s0, s1), std::max(s2, s3));
    const float close = hi - lo <= float(kDepthDiscontinuity) * lo ? 1.0f : 0.0f;
    one = lo > 0.0f ? close : 0.0f;
    const float fu = u - float(x0), fv = v - float(y0);
    const float w0 = (1 - fu) * (1 - fv), w1 = fu * (1 - fv), w2 = (1 - fu) * fv, w3 = fu * fv;
    return ((w0 * s0 + w1 * s1) + w2 * s2) + w3 * s3;
}

/// The march's rate (PortMarch::rate, max(|du|, |dv|) in double rounded to float) from du and dv
/// in float: rounding keeps the order, so this is the same float.
inline float rate_of(float du, float dv) {
    const float a = std::fabs(du), b = std::fabs(dv);
    return a < b ? b : a;
}

/// The hit point's x or y from where it projects in the input (pixel p, centre c, focal length
/// f as k = 1 / f) and its planar depth z: the point on the ray at depth z projects there, so this
/// is ray origin + t direction, without reading the ray (docs/ports.md, "Speed": within 1.5e-7 z of
/// the double trace's point).
inline float back_project(float p, float c, float k, float z) { return ((p - c) * k) * z; }

/// The input camera's centre and inverse focal lengths in float, for back_project.
struct Pinhole {
    float cx, cy, kx, ky;
    explicit Pinhole(const Camera& c)
        : cx(float(c.cx)), cy(float(c.cy)), kx(float(1.0 / c.fx)), ky(float(1.0 / c.fy)) {}
};

struct MarchScratch {
    std::vector<float> lo, hi, step, ps, ph, as, ah, bs, bh, s, start, w;
    std::vector<int> steps, side, state;
    void fit(int n) {
        for (auto* v : {&lo, &hi, &step, &ps, &ph, &as, &ah, &bs, &bh, &s, &start}) v->resize(n);
        w.resize(4 * std::size_t(n));
        for (auto* v : {&steps, &side, &state}) v->resize(n);
    }
};

/// True where some ray of the row is still in `which`.
bool any_in(int n, const int* state, int which) {
    for (int u = 0; u < n; ++u)
        if (state[u] == which) return true;
    return false;
}

/// The march of optics' march_port_ray for the rays of one row that take at most
/// kFastMarchSteps steps and whose probes all lie between four pixels of one surface: the same
/// probes, steps and Illinois steps (kFastSteps of them), lane by lane. Every other ray is
/// marked kScalar. Each ray's march starts at port_start_s where port_start_window allows
/// (`nearest`: window_nearest of inv), at s_near otherwise; the start is kept in f.start for
/// the scalar march.
DEEPSEA_CLONES
void fast_march(int n, const PortRays::MarchRow m, const float* __restrict inv,
                const float* __restrict nearest, int W, int H, float s_near, MarchScratch& f) {
    float* __restrict lo_ = f.lo.data();
    float* __restrict hi_ = f.hi.data();
    float* __restrict step_ = f.step.data();
    float* __restrict ps = f.ps.data();
    float* __restrict ph = f.ph.data();
    float* __restrict as = f.as.data();
    float* __restrict ah = f.ah.data();
    float* __restrict bs = f.bs.data();
    float* __restrict bh = f.bh.data();
    float* __restrict s_out = f.s.data();
    int* __restrict steps_ = f.steps.data();
    int* __restrict side = f.side.data();
    int* __restrict state = f.state.data();
    float* __restrict start = f.start.data();
    const float inf = std::numeric_limits<float>::infinity();
    const float still = float(kPortStillPx);
    // (the windows in a loop of their own: with the read of `nearest` in the same loop GCC
    // branches on the window and does not vectorise the masked read)
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        steps_[u] = port_start_window(m.u_inf[u], m.v_inf[u], m.du[u], m.dv[u], m.s_lo[u],
                                      m.s_hi[u], s_near, W, H);
    }
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const int window = steps_[u];
        const float window_near = nearest[window >= 0 ? window : 0];
        const float near_s = window >= 0 ? port_start_s(s_near, window_near) : s_near;
        start[u] = near_s;
        float hi = m.s_origin[u] < near_s ? m.s_origin[u] : near_s;  // (std::min's order)
        hi = hi < inf ? hi : 1e3f;
        hi = m.s_hi[u] < hi ? m.s_hi[u] : hi;
        const float lo = m.s_lo[u];
        const float moved = (hi - lo) * rate_of(m.du[u], m.dv[u]);
        float one;
        const float zh =
            probe4(inv, W, H, m.u_inf[u] + m.du[u] * hi, m.v_inf[u] + m.dv[u] * hi, one);
        const float hh = hi - zh;
        // steps of at most a pixel of the projection: ceil(moved), at least 1
        float steps = std::ceil(moved);
        steps = steps > 1.0f ? steps : 1.0f;
        steps = steps < float(kFastMarchSteps) ? steps : float(kFastMarchSteps + 1);
        // (the flags as float factors: GCC vectorises their product, not a chain of ands)
        const float simple = (m.s_origin[u] > 0.0f ? 1.0f : 0.0f) * (lo <= hi ? 1.0f : 0.0f) *
                             (moved < still ? 0.0f : 1.0f) *
                             (steps <= float(kFastMarchSteps) ? 1.0f : 0.0f) * one *
                             (hh > 0.0f ? 1.0f : 0.0f);
        state[u] = simple == 0.0f ? kScalar : kMarching;
        lo_[u] = lo;
        hi_[u] = hi;
        steps_[u] = int(steps);
        step_[u] = (hi - lo) / steps;
        ps[u] = hi;
        ph[u] = hh;
        side[u] = 0;
    }
    // Toward the vanishing point, a step at a time: the first probe behind the surface brackets
    // the crossing with the one before it (in front).
    for (int i = 1; i <= kFastMarchSteps && any_in(n, state, kMarching); ++i) {
#pragma omp simd
        for (int u = 0; u < n; ++u) {
            const int st = state[u];
            const bool last = i == steps_[u];
            const bool marching = (st == kMarching) & (i <= steps_[u]);
            const float s = last ? lo_[u] : hi_[u] - step_[u] * float(i);
            float one;
            const float iz =
                probe4(inv, W, H, m.u_inf[u] + m.du[u] * s, m.v_inf[u] + m.dv[u] * s, one);
            const float h = s - iz;
            const bool cross = h <= 0.0f;
            as[u] = marching ? ps[u] : as[u];
            ah[u] = marching ? ph[u] : ah[u];
            bs[u] = marching ? s : bs[u];
            bh[u] = marching ? h : bh[u];
            ps[u] = marching ? s : ps[u];
            ph[u] = marching ? h : ph[u];
            const int none = lo_[u] == 0.0f ? kOpen : kUnseen;
            state[u] = !marching     ? st
                       : one == 0.0f ? kScalar
                       : cross       ? (h < 0.0f ? kActive : kScalar)
                       : last        ? none
                                     : kMarching;
        }
    }
    const float tol = kPortHitToleranceFloat, span = 4 * std::numeric_limits<float>::epsilon();
    for (int step = 0; step < kFastSteps && any_in(n, state, kActive); ++step) {
#pragma omp simd
        for (int u = 0; u < n; ++u) {
            float a_s = as[u], a_h = ah[u], b_s = bs[u], b_h = bh[u];
            float s = (a_s * b_h - b_s * a_h) / (b_h - a_h);
            s = s < a_s && s > b_s ? s : 0.5f * (a_s + b_s);
            float one;
            const float iz =
                probe4(inv, W, H, m.u_inf[u] + m.du[u] * s, m.v_inf[u] + m.dv[u] * s, one);
            const float h = s - iz;
            // Illinois: the side that stays twice running has its h halved
            const int sd = side[u];
            const bool front = h > 0.0f;
            const float a_s2 = front ? s : a_s, b_s2 = front ? b_s : s;
            const float a_h2 = front ? h : (sd == -1 ? a_h * 0.5f : a_h);
            const float b_h2 = front ? (sd == 1 ? b_h * 0.5f : b_h) : h;
            const bool on = std::fabs(h) <= tol * (s + iz);
            const bool collapsed =
                ((a_s2 - b_s2) * rate_of(m.du[u], m.dv[u]) <= tol) | (a_s2 - b_s2 <= span * a_s2);
            const int st = state[u];
            const bool active = st == kActive;
            as[u] = active ? a_s2 : a_s;
            ah[u] = active ? a_h2 : a_h;
            bs[u] = active ? b_s2 : b_s;
            bh[u] = active ? b_h2 : b_h;
            side[u] = active ? (front ? 1 : -1) : sd;
            s_out[u] = active ? s : s_out[u];
            state[u] = !active       ? st
                       : one == 0.0f ? kScalar
                       : on          ? kSurface
                       : collapsed   ? kScalar
                                     : kActive;
        }
    }
}

/// The hits that fast_march settled on one surface (kSurface): the point, the path from the
/// port, and the normal and colour from the four input pixels around the hit, with the scalar
/// code's arithmetic (port_row's; taps_at's weights). Other lanes get zeros. Lane by lane the
/// taps' positions and weights, then per pixel two 4-float loads a tap (the interleaved
/// normal and colour; gathering each float costs more), then the normals' lengths.
DEEPSEA_CLONES
void surface_hits(int n, const PortRays::MarchRow m, const Pinhole cam, const float* __restrict in,
                  int W, int H, MarchScratch& f, const PortRow& o) {
    const float* __restrict s_hit = f.s.data();
    const int* __restrict state = f.state.data();
    int* __restrict at = f.steps.data();  // (spent by now)
    float* __restrict w = f.w.data();
    float* __restrict x = o.x, * __restrict y = o.y, * __restrict z = o.z, * __restrict t = o.t;
    float* __restrict nx = o.nx, * __restrict ny = o.ny, * __restrict nz = o.nz;
    float* __restrict J = o.J, * __restrict mask = o.mask;
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const bool hit = state[u] == kSurface;
        const float s_u = s_hit[u];
        const float s = hit ? s_u : 1.0f;  // (any finite s: the taps stay in the image)
        const float hu = m.u_inf[u] + m.du[u] * s, hv = m.v_inf[u] + m.dv[u] * s;
        float pu = hu > 0.0f ? hu : 0.0f, pv = hv > 0.0f ? hv : 0.0f;
        pu = pu < float(W - 1) ? pu : float(W - 1);
        pv = pv < float(H - 1) ? pv : float(H - 1);
        const int x0 = std::min(int(pu), W - 2), y0 = std::min(int(pv), H - 2);
        const float fu = pu - float(x0), fv = pv - float(y0);
        at[u] = (y0 * W + x0) * kPortSurfaceChannels;
        w[4 * u] = hit ? (1 - fu) * (1 - fv) : 0.0f;
        w[4 * u + 1] = hit ? fu * (1 - fv) : 0.0f;
        w[4 * u + 2] = hit ? (1 - fu) * fv : 0.0f;
        w[4 * u + 3] = hit ? fu * fv : 0.0f;
        // the point at the hit's planar depth on the ray, from where it projects
        const float zh = 1.0f / s, th = (zh - m.oz[u]) / m.dz[u];
        x[u] = hit ? back_project(hu, cam.cx, cam.kx, zh) : 0.0f;
        y[u] = hit ? back_project(hv, cam.cy, cam.ky, zh) : 0.0f;
        z[u] = hit ? zh : 0.0f;
        t[u] = hit ? th : 0.0f;
        mask[u] = (hit | (state[u] == kOpen)) ? 1.0f : 0.0f;
    }
    const std::size_t row = std::size_t(W) * kPortSurfaceChannels, C = kPortSurfaceChannels;
    for (int u = 0; u < n; ++u) {
        const float* p = in + at[u];
        const Float4 w0 = splat(w[4 * u]), w1 = splat(w[4 * u + 1]), w2 = splat(w[4 * u + 2]),
                     w3 = splat(w[4 * u + 3]);
        const Float4 N =
            ((w0 * load4(p) + w1 * load4(p + C)) + w2 * load4(p + row)) + w3 * load4(p + row + C);
        const Float4 j = ((w0 * load4(p + 4) + w1 * load4(p + C + 4)) + w2 * load4(p + row + 4)) +
                         w3 * load4(p + row + C + 4);
        nx[u] = N[0];
        ny[u] = N[1];
        nz[u] = N[2];
        J[3 * u] = j[0];
        J[3 * u + 1] = j[1];
        J[3 * u + 2] = j[2];
    }
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float len = std::sqrt(nx[u] * nx[u] + ny[u] * ny[u] + nz[u] * nz[u]);
        const float inv = len > 0.0f ? 1.0f / len : 0.0f;
        nx[u] *= inv;
        ny[u] *= inv;
        nz[u] *= inv;
    }
}

}  // namespace

void port_row(const PortRays& rays, int v, const Image& inv_depth, const Image& nearest,
              const Image& surface, double z_near, const PortRow& o) {
    const int W = rays.camera().width;
    const Pinhole cam(rays.camera());
    const float s_near = float(1.001 / z_near);
    const float* in = surface.data.data();
    thread_local MarchScratch f;
    f.fit(W);
    const bool fast = inv_depth.width >= 2 && inv_depth.height >= 2;
    if (fast) {
        fast_march(W, rays.march_row(v), inv_depth.data.data(), nearest.data.data(),
                   inv_depth.width, inv_depth.height, s_near, f);
        surface_hits(W, rays.march_row(v), cam, in, inv_depth.width, inv_depth.height, f, o);
    }
    // The rest, one by one (rare: depth edges, open water, long marches)
    for (int u = 0; u < W; ++u) {
        const int st = fast ? f.state[u] : kScalar;
        if (st == kSurface || st == kOpen || st == kUnseen) continue;  // (done above)
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
        const float z = 1.0f / h.s, t = (z - r.oz) / r.dz;
        o.x[u] = back_project(m.u_inf + m.du * h.s, cam.cx, cam.kx, z);
        o.y[u] = back_project(m.v_inf + m.dv * h.s, cam.cy, cam.ky, z);
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
