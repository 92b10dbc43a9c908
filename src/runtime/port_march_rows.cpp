// The march's common case vectorised across a row (docs/port-speed.md, item 2): compiled
// with -fopenmp-simd, -ffp-contract=off and -fno-trapping-math (see CMakeLists.txt), not
// fast-math, so that its lanes do the scalar march's float arithmetic exactly and give the same
// hits.

#include <algorithm>
#include <cmath>
#include <limits>

#include "clones.h"
#include "port_lanes.h"

namespace deepsea::port_lanes {

namespace {

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

}  // namespace

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

}  // namespace deepsea::port_lanes
