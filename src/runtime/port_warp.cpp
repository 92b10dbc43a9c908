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

// (settle_hits' Float8 values live in registers inside it: no call passes one, so GCC's note that
// AVX changes the ABI of such calls does not apply to its generic clone)
#pragma GCC diagnostic ignored "-Wpsabi"

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

/// The steps of at most a pixel tried across the row (then one Illinois step, in settle_hits)
/// before a ray is left to the scalar march.
constexpr int kFastMarchSteps = 8;

/// The 2 x 2 cell that port_detail::taps_at reads at (u, v) (its clamped position; W, H >= 2):
/// the index y0 W + x0 of its upper-left pixel (gather_cells' at), and the position's fractions
/// fu, fv in it. NaN positions read pixel 0 (the ray is then left to the scalar march).
inline int cell_at(int W, int H, float u, float v, float& fu, float& fv) {
    u = u > 0.0f ? u : 0.0f;
    u = u < float(W - 1) ? u : float(W - 1);
    v = v > 0.0f ? v : 0.0f;
    v = v < float(H - 1) ? v : float(H - 1);
    const int x0 = std::min(int(u), W - 2), y0 = std::min(int(v), H - 2);
    fu = u - float(x0);
    fv = v - float(y0);
    return y0 * W + x0;
}

/// taps_at's value from the cell's four inverse depths (cell_at's, in gather_cells' order) where
/// they are one surface (the same arithmetic); `one` is 0 where taps_at would take the nearest
/// pixel or open water.
inline float cell_probe(float s0, float s1, float s2, float s3, float fu, float fv, float& one) {
    const float lo = std::min(std::min(s0, s1), std::min(s2, s3));
    const float hi = std::max(std::max(s0, s1), std::max(s2, s3));
    const float close = hi - lo <= float(kDepthDiscontinuity) * lo ? 1.0f : 0.0f;
    one = lo > 0.0f ? close : 0.0f;
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
    std::vector<float> lo, hi, step, ps, ph, as, ah, bs, bh, s, start, w, ok, fu[2], fv[2], c[8];
    std::vector<int> steps, state, at[2];
    void fit(int n) {
        for (auto* v : {&lo, &hi, &step, &ps, &ph, &as, &ah, &bs, &bh, &s, &start, &ok})
            v->resize(n);
        for (auto& v : fu) v.resize(n);
        for (auto& v : fv) v.resize(n);
        for (auto& v : c) v.resize(n);
        w.resize(4 * std::size_t(n));
        for (auto* v : {&steps, &state, &at[0], &at[1]}) v->resize(n);
    }
};

/// fast_march's scratch as plain pointers, for march_step: besides the march's state, two
/// probes' cells (cell_at, gather_cells: at, fu, fv; c0-c3 the first's inverse depths, c4-c7
/// the second's).
struct MarchLanes {
    float *lo, *hi, *step, *ps, *ph, *as, *ah, *bs, *bh;
    int *steps, *state;
    int* at[2];
    float *fu[2], *fv[2], *c[8];
    explicit MarchLanes(MarchScratch& f)
        : lo(f.lo.data()),
          hi(f.hi.data()),
          step(f.step.data()),
          ps(f.ps.data()),
          ph(f.ph.data()),
          as(f.as.data()),
          ah(f.ah.data()),
          bs(f.bs.data()),
          bh(f.bh.data()),
          steps(f.steps.data()),
          state(f.state.data()) {
        for (int k = 0; k < 2; ++k) {
            at[k] = f.at[k].data();
            fu[k] = f.fu[k].data();
            fv[k] = f.fv[k].data();
        }
        for (int k = 0; k < 8; ++k) c[k] = f.c[k].data();
    }
    /// The inverse depth at probe k's position in lane u (cell_probe of its gathered cell).
    float probe(int k, int u, float& one) const {
        return cell_probe(c[4 * k][u], c[4 * k + 1][u], c[4 * k + 2][u], c[4 * k + 3][u], fu[k][u],
                          fv[k][u], one);
    }
    /// The gather of probe k's cells (in c[4 k] .. c[4 k + 3]).
    void gather(int k, int n, const float* inv, int W) const {
        gather_cells(n, at[k], inv, W, c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]);
    }
};

/// Where step i of fast_march probes lane u's ray (the vanishing point's side of the view at the
/// last step).
__attribute__((always_inline)) inline float step_s(int u, int i, const MarchLanes& f) {
    return i == f.steps[u] ? f.lo[u] : f.hi[u] - f.step[u] * float(i);
}

/// Step i of fast_march for lane u, at s = step_s with the inverse depth iz there (and `one`,
/// cell_probe's): the bracket where it is the first probe behind the surface. kFirst (i = 1): no
/// lane holds a bracket yet, so the bracket and the previous probe are written in every lane
/// (those not marching never read them), plain stores instead of masked ones, which cost many
/// times as much on some x86 cores. Returns 1 where the ray is still marching after it.
template <bool kFirst>
__attribute__((always_inline)) inline int march_step(int u, int i, float s, float iz, float one,
                                                     const MarchLanes& f) {
    const int st = f.state[u];
    const int n_steps = f.steps[u];
    const bool last = i == n_steps;
    const bool marching = (st == kMarching) & (i <= n_steps);
    const float h = s - iz;
    const bool cross = h <= 0.0f;
    const bool keep = !kFirst & !marching;
    f.as[u] = keep ? f.as[u] : f.ps[u];
    f.ah[u] = keep ? f.ah[u] : f.ph[u];
    f.bs[u] = keep ? f.bs[u] : s;
    f.bh[u] = keep ? f.bh[u] : h;
    f.ps[u] = keep ? f.ps[u] : s;
    f.ph[u] = keep ? f.ph[u] : h;
    const int none = f.lo[u] == 0.0f ? kOpen : kUnseen;
    const int next = !marching     ? st
                     : one == 0.0f ? kScalar
                     : cross       ? (h < 0.0f ? kActive : kScalar)
                     : last        ? none
                                   : kMarching;
    f.state[u] = next;
    return next == kMarching ? 1 : 0;
}

/// The march of optics' march_port_ray for the rays of one row that take at most
/// kFastMarchSteps steps and whose probes all lie between four pixels of one surface: the same
/// probes and steps, lane by lane, up to the bracket of the first crossing (kActive: in front at
/// f.as, f.ah, behind at f.bs, f.bh), whose Illinois step settle_hits takes. Every other ray is
/// marked kScalar. Each ray's march starts at port_start_s where port_start_window allows
/// (`nearest`: window_nearest of inv), at s_near otherwise; the start is kept in f.start for
/// the scalar march. Each probe in three loops: the positions and cells, their inverse depths
/// (gather_cells), the rest; the start's probe and the first step's share their loops.
DEEPSEA_CLONES
void fast_march(int n, const PortRays::MarchRow m, const float* __restrict inv,
                const float* __restrict nearest, int W, int H, float s_near, MarchScratch& f) {
    float* __restrict lo_ = f.lo.data();
    float* __restrict hi_ = f.hi.data();
    float* __restrict step_ = f.step.data();
    float* __restrict ok = f.ok.data();
    int* __restrict steps_ = f.steps.data();
    int* __restrict state = f.state.data();
    float* __restrict start = f.start.data();
    const MarchLanes lanes(f);
    int* __restrict at0 = lanes.at[0];
    int* __restrict at1 = lanes.at[1];
    float* __restrict fu0 = lanes.fu[0];
    float* __restrict fv0 = lanes.fv[0];
    float* __restrict fu1 = lanes.fu[1];
    float* __restrict fv1 = lanes.fv[1];
    const float inf = std::numeric_limits<float>::infinity();
    const float still = float(kPortStillPx);
    int marching = 0;  // (the rays still marching: counted in the loops, not by a scan of the row)
    // (the windows in a loop of their own: with the read of `nearest` in the same loop GCC
    // branches on the window and does not vectorise the masked read)
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        steps_[u] = port_start_window(m.u_inf[u], m.v_inf[u], m.du[u], m.dv[u], m.s_lo[u],
                                      m.s_hi[u], s_near, W, H);
    }
    // The start, the steps, and the cells of the start's probe (0) and the first step's (1).
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
        // steps of at most a pixel of the projection: ceil(moved), at least 1
        float steps = std::ceil(moved);
        steps = steps > 1.0f ? steps : 1.0f;
        steps = steps < float(kFastMarchSteps) ? steps : float(kFastMarchSteps + 1);
        // (the flags as float factors: GCC vectorises their product, not a chain of ands)
        ok[u] = (m.s_origin[u] > 0.0f ? 1.0f : 0.0f) * (lo <= hi ? 1.0f : 0.0f) *
                (moved < still ? 0.0f : 1.0f) * (steps <= float(kFastMarchSteps) ? 1.0f : 0.0f);
        const float step = (hi - lo) / steps;
        lo_[u] = lo;
        hi_[u] = hi;
        steps_[u] = int(steps);
        step_[u] = step;
        at0[u] =
            cell_at(W, H, m.u_inf[u] + m.du[u] * hi, m.v_inf[u] + m.dv[u] * hi, fu0[u], fv0[u]);
        const float s1 = 1 == int(steps) ? lo : hi - step * float(1);  // (step_s's)
        at1[u] =
            cell_at(W, H, m.u_inf[u] + m.du[u] * s1, m.v_inf[u] + m.dv[u] * s1, fu1[u], fv1[u]);
    }
    lanes.gather(0, n, inv, W);
    lanes.gather(1, n, inv, W);
    // The start's probe: the rays in front of the surface there march; then the first step
    // toward the vanishing point, whose probe brackets the crossing with the start's where it is
    // behind the surface.
#pragma omp simd reduction(+ : marching)
    for (int u = 0; u < n; ++u) {
        float one;
        const float hi = hi_[u], hh = hi - lanes.probe(0, u, one);
        const float simple = ok[u] * one * (hh > 0.0f ? 1.0f : 0.0f);
        state[u] = simple == 0.0f ? kScalar : kMarching;
        lanes.ps[u] = hi;
        lanes.ph[u] = hh;
        float one1;
        const float iz = lanes.probe(1, u, one1);
        marching += march_step<true>(u, 1, step_s(u, 1, lanes), iz, one1, lanes);
    }
    // Toward the vanishing point, a step at a time (rarely more than one).
    for (int i = 2; i <= kFastMarchSteps && marching > 0; ++i) {
        marching = 0;
#pragma omp simd
        for (int u = 0; u < n; ++u) {
            const float s = step_s(u, i, lanes);
            at0[u] =
                cell_at(W, H, m.u_inf[u] + m.du[u] * s, m.v_inf[u] + m.dv[u] * s, fu0[u], fv0[u]);
        }
        lanes.gather(0, n, inv, W);
#pragma omp simd reduction(+ : marching)
        for (int u = 0; u < n; ++u) {
            float one;
            const float iz = lanes.probe(0, u, one);
            marching += march_step<false>(u, i, step_s(u, i, lanes), iz, one, lanes);
        }
    }
}

/// The four lanes of a Float8: its first (lo) or its last (hi).
inline Float4 low4(Float8 v) { return __builtin_shufflevector(v, v, 0, 1, 2, 3); }
inline Float4 high4(Float8 v) { return __builtin_shufflevector(v, v, 4, 5, 6, 7); }
/// Lane k of each half of v in that half (one in-lane permute).
template <int k>
inline Float8 splat_halves(Float8 v) {
    return __builtin_shufflevector(v, v, k, k, k, k, k + 4, k + 4, k + 4, k + 4);
}

/// settle_hits' taps of lane u: one 8-float load a tap from the interleaved surface at p (the
/// 2 x 2 pixels from p, `row` floats a row), weighted by the four weights at w[4 u]. The sums'
/// lanes 0-3 (the normal and the inverse depth) replace the weights, the four pixels' least and
/// largest inverse depth (lane 3: cell_probe's test of one surface) go to lo_z[u], hi_z[u]; the
/// colour's sums (lanes 4-7; 7 is the surface's 0) are returned. The products and sums are
/// four-float arithmetic's, lane by lane, so the same floats as the scalar march's taps.
__attribute__((always_inline)) inline Float4 settle_taps(const float* p, std::size_t row, int u,
                                                         float* w, float* lo_z, float* hi_z) {
    constexpr std::size_t C = kPortSurfaceChannels;
    const Float8 t0 = load8(p), t1 = load8(p + C), t2 = load8(p + row), t3 = load8(p + row + C);
    // (the weights in both halves, one load, then each broadcast by an in-lane permute: GCC
    // makes a broadcast of lane k > 0 of a Float4 from two shuffles, of a float from three)
    const Float4 wu = load4(w + 4 * u);
    const Float8 w8 = __builtin_shufflevector(wu, wu, 0, 1, 2, 3, 0, 1, 2, 3);
    const Float8 N =
        ((splat_halves<0>(w8) * t0 + splat_halves<1>(w8) * t1) + splat_halves<2>(w8) * t2) +
        splat_halves<3>(w8) * t3;
    store4(w + 4 * u, low4(N));
    // (std::min's and std::max's order, four lanes at a time, of which lane 3 is kept: three
    // vector instructions each instead of extracting four lanes and comparing them one by one)
    const Float4 a0 = low4(t0), a1 = low4(t1), a2 = low4(t2), a3 = low4(t3);
    lo_z[u] = min4(min4(a0, a1), min4(a2, a3))[3];
    hi_z[u] = max4(max4(a0, a1), max4(a2, a3))[3];
    return high4(N);
}

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
        // regula falsi between the bracket's ends, bisection where it falls outside
        const float a_s = as[u], a_h = ah[u], b_s = bs[u], b_h = bh[u];
        float s = (a_s * b_h - b_s * a_h) / (b_h - a_h);
        s = s < a_s && s > b_s ? s : 0.5f * (a_s + b_s);
        s = active ? s : 0.0f;  // (the vanishing point: its taps lie in PortRays::reach)
        s_hit[u] = s;
        const float hu = m.u_inf[u] + m.du[u] * s, hv = m.v_inf[u] + m.dv[u] * s;
        float pu = hu > 0.0f ? hu : 0.0f, pv = hv > 0.0f ? hv : 0.0f;
        pu = pu < float(W - 1) ? pu : float(W - 1);
        pv = pv < float(H - 1) ? pv : float(H - 1);
        const int x0 = std::min(int(pu), W - 2), y0 = std::min(int(pv), H - 2);
        const float fu = pu - float(x0), fv = pv - float(y0);
        at[u] = (y0 * W + x0) * kPortSurfaceChannels;
        w[4 * u] = active ? (1 - fu) * (1 - fv) : 0.0f;
        w[4 * u + 1] = active ? fu * (1 - fv) : 0.0f;
        w[4 * u + 2] = active ? (1 - fu) * fv : 0.0f;
        w[4 * u + 3] = active ? fu * fv : 0.0f;
    }
    const std::size_t row = std::size_t(W) * kPortSurfaceChannels;
    constexpr int kAhead = 16;
    // (the loop split where the prefetch ends, so that no pixel tests whether it prefetches; the
    // colour stored four floats at a time, the fourth overwritten by the next pixel's red, but for
    // the row's last pixel, whose fourth would lie beyond the row)
    const int ahead_end = std::max(n - kAhead, 0);
    for (int u = 0; u < ahead_end; ++u) {
        __builtin_prefetch(in + at[u + kAhead]);
        __builtin_prefetch(in + at[u + kAhead] + row);
        store4(J + 3 * u, settle_taps(in + at[u], row, u, w, lo_z, hi_z));
    }
    for (int u = ahead_end; u < n - 1; ++u)
        store4(J + 3 * u, settle_taps(in + at[u], row, u, w, lo_z, hi_z));
    if (n > 0) {
        const Float4 j = settle_taps(in + at[n - 1], row, n - 1, w, lo_z, hi_z);
        for (int c = 0; c < 3; ++c) J[3 * (n - 1) + c] = j[c];
    }
    const float edge = float(kDepthDiscontinuity), tol = kPortHitToleranceFloat;
    int left = 0;
#pragma omp simd reduction(+ : left)
    for (int u = 0; u < n; ++u) {
        const int st = state[u];
        const float iz = w[4 * u + 3], lo = lo_z[u], hi = hi_z[u];
        const float s = s_hit[u], h = s - iz;
        // on the surface, between four pixels of one surface: the scalar march's hit; any
        // other outcome of the step is left to it
        const bool one = (lo > 0.0f) & (hi - lo <= edge * lo);
        const bool on = std::fabs(h) <= tol * (s + iz);
        const bool hit = (st == kActive) & one & on;
        const int next = hit ? kSurface : st == kActive ? kScalar : st;
        state[u] = next;
        left += (next == kSurface) | (next == kOpen) | (next == kUnseen) ? 0 : 1;
        const float hu = m.u_inf[u] + m.du[u] * s, hv = m.v_inf[u] + m.dv[u] * s;
        // the point at the hit's planar depth on the ray, from where it projects
        const float zh = 1.0f / s, th = (zh - m.oz[u]) / m.dz[u];
        x[u] = hit ? back_project(hu, cam.cx, cam.kx, zh) : 0.0f;
        y[u] = hit ? back_project(hv, cam.cy, cam.ky, zh) : 0.0f;
        z[u] = hit ? zh : 0.0f;
        t[u] = hit ? th : 0.0f;
        mask[u] = (hit | (st == kOpen)) ? 1.0f : 0.0f;
        const float Nx = w[4 * u], Ny = w[4 * u + 1], Nz = w[4 * u + 2];
        const float len = std::sqrt(Nx * Nx + Ny * Ny + Nz * Nz);
        const float inv = len > 0.0f ? 1.0f / len : 0.0f;
        nx[u] = Nx * inv;
        ny[u] = Ny * inv;
        nz[u] = Nz * inv;
    }
    return left;
}

}  // namespace

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
