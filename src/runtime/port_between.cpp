// The port's rows' bounded approximation (Compositor::set_exact(false); docs/ports.md, "Speed"):
// the exact march on every other pixel of a row, the pixels between from their neighbours' hits.
// Compiled like the march (port_lanes.h): the even pixels' hits are the exact path's bit for bit.

#include <algorithm>
#include <cmath>

#include "clones.h"
#include "port_lanes.h"

namespace deepsea::port_lanes {

namespace {

/// Field p of a row's march constants for the even pixels 0, 2, 4 ... (ne of them): a copy in
/// `even` where p is a plane of the table (raw, march_row(v)'s), p itself where it is a row of
/// constants (march_row(v, s_near)'s, the same value in every place).
const float* even_field(const float* p, const float* raw, int ne, std::vector<float>& even) {
    if (p != raw) return p;
    float* __restrict e = even.data();
#pragma omp simd
    for (int k = 0; k < ne; ++k) e[k] = p[2 * k];
    return e;
}

/// The odd pixel's hit from where its neighbours' s predicts it (s, lane u of row m, its cell's
/// four inverse depths c and the position's fractions fu, fv in it): one Newton step on the
/// cell's bilinear surface, h(s) = s - S(u'(s), v'(s)) with S's derivative along the ray's
/// projection (du, dv); on a plane, where S is affine in s, the root. Returns the step's s;
/// `ok` where it stays in the cell, moves the projection at most kBetweenShiftPx, and lands on
/// the surface to the float march's tolerance (the cell's own bilinear value there, taps_at's
/// arithmetic).
inline float newton_between(float s, float iz, float du, float dv, const float* c, float fu,
                            float fv, bool& ok) {
    const float gu = (1 - fv) * (c[1] - c[0]) + fv * (c[3] - c[2]);
    const float gv = (1 - fu) * (c[2] - c[0]) + fu * (c[3] - c[1]);
    const float slope = 1.0f - (du * gu + dv * gv);  // dh / ds: > 0 where the ray enters it
    const float step = slope > 0.0f ? (s - iz) / slope : 0.0f;
    const float sn = s - step;
    const float fu2 = fu - du * step, fv2 = fv - dv * step;
    const float w0 = (1 - fu2) * (1 - fv2), w1 = fu2 * (1 - fv2), w2 = (1 - fu2) * fv2,
                w3 = fu2 * fv2;
    const float Sn = ((w0 * c[0] + w1 * c[1]) + w2 * c[2]) + w3 * c[3];
    const bool inside = (fu2 >= 0.0f) & (fu2 <= 1.0f) & (fv2 >= 0.0f) & (fv2 <= 1.0f);
    ok = (slope > 0.0f) & inside & (std::fabs(step) * rate_of(du, dv) <= kBetweenShiftPx) &
         (std::fabs(sn - Sn) <= kPortHitToleranceFloat * (sn + Sn));
    return sn;
}

/// The row's hits from the probe s of each pixel (s_px; state_px kActive where there is one:
/// the even pixels' Illinois step after their march, the odd pixels' prediction), with the taps
/// of settle_hits: lane by lane the taps' positions and weights, per pixel the taps (with the
/// cell's inverse depths), lane by lane the outcomes (the even pixels' as settle_hits', the odd
/// pixels' Newton step where both neighbours settle), then the outputs. Returns the number of
/// rays left to the scalar march.
DEEPSEA_CLONES
int settle_between(int n, const PortRays::MarchRow m, const Pinhole cam, const float* __restrict in,
                   int W, int H, MarchScratch& f, const PortRow& o) {
    float* __restrict s_px = f.s_px.data();
    int* __restrict state = f.state_px.data();
    int* __restrict at = f.steps.data();
    float* __restrict fu_px = f.fu_px.data();
    float* __restrict fv_px = f.fv_px.data();
    float* __restrict ok = f.ok.data();  // (n + 2: ok[u + 1] the pixel's, 0 beyond the row)
    float* __restrict lo_z = f.ps.data();
    float* __restrict hi_z = f.ph.data();
    float* __restrict cell = f.cell.data();
    float* __restrict w = f.w.data();
    float* __restrict x = o.x, * __restrict y = o.y, * __restrict z = o.z, * __restrict t = o.t;
    float* __restrict nx = o.nx, * __restrict ny = o.ny, * __restrict nz = o.nz;
    float* __restrict mask = o.mask;
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const bool active = state[u] == kActive;
        const float s = active ? s_px[u] : 0.0f;  // (the vanishing point, as settle_hits')
        s_px[u] = s;
        const float hu = m.u_inf[u] + m.du[u] * s, hv = m.v_inf[u] + m.dv[u] * s;
        place_taps(hu, hv, W, H, active, at[u], w + 4 * u, fu_px[u], fv_px[u]);
        // (a clamped position's cell is not the ray's: no Newton step there)
        const bool inside =
            (hu >= 0.0f) & (hu <= float(W - 1)) & (hv >= 0.0f) & (hv <= float(H - 1));
        ok[u + 1] = inside ? 1.0f : 0.0f;
    }
    taps_row<true>(n, in, at, std::size_t(W) * kPortSurfaceChannels, w, lo_z, hi_z, cell, o.J);
    ok[0] = 0.0f;
    ok[n + 1] = 0.0f;
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float s = s_px[u], iz = w[4 * u + 3];
        bool newton = false;
        const float sn =
            newton_between(s, iz, m.du[u], m.dv[u], cell + 4 * u, fu_px[u], fv_px[u], newton);
        const bool odd = (u & 1) != 0;
        // even: settle_hits' test; odd: one surface, and the Newton step's own
        const bool here = (state[u] == kActive) &
                          (odd ? one_surface(lo_z[u], hi_z[u]) & newton & (ok[u + 1] != 0.0f)
                               : settles(lo_z[u], hi_z[u], s, iz));
        // (the odd pixels' s: the Newton step's; their taps stay where the prediction put them)
        s_px[u] = odd ? sn : s;
        ok[u + 1] = here ? 1.0f : 0.0f;
    }
    int left = 0;
#pragma omp simd reduction(+ : left)
    for (int u = 0; u < n; ++u) {
        const int st = state[u];
        const bool odd = (u & 1) != 0;
        // an odd pixel's hit only where both neighbours' are: they lie on one surface
        const bool hit = (ok[u + 1] != 0.0f) & (odd ? (ok[u] != 0.0f) & (ok[u + 2] != 0.0f) : true);
        const int next = hit ? kSurface : st == kActive ? kScalar : st;
        state[u] = next;
        left += (next == kSurface) | (next == kOpen) | (next == kUnseen) ? 0 : 1;
        const float s = s_px[u];
        float xh, yh, zh, th;
        hit_point(m.u_inf[u] + m.du[u] * s, m.v_inf[u] + m.dv[u] * s, s, m.oz[u], m.dz[u], cam, xh,
                  yh, zh, th);
        x[u] = hit ? xh : 0.0f;
        y[u] = hit ? yh : 0.0f;
        z[u] = hit ? zh : 0.0f;
        t[u] = hit ? th : 0.0f;
        mask[u] = (hit | (st == kOpen)) ? 1.0f : 0.0f;
        unit_normal(w + 4 * u, nx[u], ny[u], nz[u]);
    }
    return left;
}

}  // namespace

/// The odd pixels that settle_between left to the scalar march (their neighbours not on one
/// surface, or the row's last pixel), each marched as the exact path marches it: fast_march and
/// settle_hits on them alone, then the scalar march for those they leave. Returns the number of
/// rays left to the scalar march.
int retry_odd(int left, const PortRays::MarchRow m, const PortRays::MarchRow raw, float s_near,
              const Pinhole& cam, const float* in, const float* inv, const float* nearest, int W,
              int H, MarchScratch& f, const PortRow& o) {
    int* state = f.state_px.data();
    int* idx = f.retry.data();
    int nr = 0;
    for (int u = 1; u < W; u += 2)
        if (state[u] == kScalar) idx[nr++] = u;
    if (nr == 0) return left;
    const auto pick = [&](const float* p, const float* r, std::vector<float>& out) {
        if (p != r) return p;  // (a row of constants)
        for (int k = 0; k < nr; ++k) out[k] = p[idx[k]];
        return static_cast<const float*>(out.data());
    };
    PortRays::MarchRow mr;
    mr.u_inf = pick(m.u_inf, raw.u_inf, f.even[0]);
    mr.v_inf = pick(m.v_inf, raw.v_inf, f.even[1]);
    mr.du = pick(m.du, raw.du, f.even[2]);
    mr.dv = pick(m.dv, raw.dv, f.even[3]);
    mr.s_origin = pick(m.s_origin, raw.s_origin, f.even[4]);
    mr.s_lo = pick(m.s_lo, raw.s_lo, f.even[5]);
    mr.s_hi = pick(m.s_hi, raw.s_hi, f.even[6]);
    mr.oz = pick(m.oz, raw.oz, f.even[7]);
    mr.dz = pick(m.dz, raw.dz, f.even[8]);
    fast_march(nr, mr, inv, nearest, W, H, s_near, f);
    float* r = f.retry_out.data();
    const std::size_t N = std::size_t(nr);
    const PortRow t{r,         r + N,     r + 2 * N, r + 3 * N, r + 4 * N,
                    r + 5 * N, r + 6 * N, r + 8 * N, r + 7 * N};
    const int still = settle_hits(nr, mr, cam, in, W, H, f, t);
    for (int k = 0; k < nr; ++k) {
        const int u = idx[k];
        o.x[u] = t.x[k];
        o.y[u] = t.y[k];
        o.z[u] = t.z[k];
        o.t[u] = t.t[k];
        o.nx[u] = t.nx[k];
        o.ny[u] = t.ny[k];
        o.nz[u] = t.nz[k];
        o.mask[u] = t.mask[k];
        for (int c = 0; c < 3; ++c) o.J[3 * u + c] = t.J[3 * k + c];
        state[u] = f.state[k];
        f.start_px[u] = f.start[k];
    }
    return left - nr + still;
}

DEEPSEA_CLONES
int between_row(const PortRays& rays, int v, float s_near, const Pinhole& cam, const float* in,
                const float* inv, const float* nearest, int W, int H, MarchScratch& f,
                const PortRow& o) {
    const PortRays::MarchRow m = rays.march_row(v, s_near), raw = rays.march_row(v);
    const int ne = (W + 1) / 2;
    // The even pixels' march, exactly as the exact path marches them (fast_march's lanes are
    // independent of each other)
    PortRays::MarchRow me;
    me.u_inf = even_field(m.u_inf, raw.u_inf, ne, f.even[0]);
    me.v_inf = even_field(m.v_inf, raw.v_inf, ne, f.even[1]);
    me.du = even_field(m.du, raw.du, ne, f.even[2]);
    me.dv = even_field(m.dv, raw.dv, ne, f.even[3]);
    me.s_origin = even_field(m.s_origin, raw.s_origin, ne, f.even[4]);
    me.s_lo = even_field(m.s_lo, raw.s_lo, ne, f.even[5]);
    me.s_hi = even_field(m.s_hi, raw.s_hi, ne, f.even[6]);
    me.oz = even_field(m.oz, raw.oz, ne, f.even[7]);
    me.dz = even_field(m.dz, raw.dz, ne, f.even[8]);
    fast_march(ne, me, inv, nearest, W, H, s_near, f);
    // Each pixel's probe: the even pixels' Illinois step (settle_hits'), the odd pixels' midway
    // between their neighbours' where both are bracketed on one surface
    const int* __restrict st = f.state.data();
    float* __restrict s_e = f.s.data();
    const float *as = f.as.data(), *ah = f.ah.data(), *bs = f.bs.data(), *bh = f.bh.data();
#pragma omp simd
    for (int k = 0; k < ne; ++k) s_e[k] = illinois_step(as[k], ah[k], bs[k], bh[k]);
    float* __restrict s_px = f.s_px.data();
    int* __restrict state = f.state_px.data();
    float* __restrict start = f.start_px.data();
    const float* __restrict start_e = f.start.data();
#pragma omp simd
    for (int k = 0; k < ne; ++k) {
        s_px[2 * k] = s_e[k];
        state[2 * k] = st[k];
        start[2 * k] = start_e[k];
    }
    const float edge = float(kDepthDiscontinuity);
    // (k + 1 = ne, past the last even pixel, is read from the scratch but not used)
#pragma omp simd
    for (int k = 0; k < W / 2; ++k) {
        const bool both = (k + 1 < ne) & (st[k] == kActive) & (st[k + 1] == kActive);
        const float a = s_e[k], b = s_e[k + 1];
        const float lo = a < b ? a : b, hi = a < b ? b : a;
        const bool near = both & (hi - lo <= edge * lo);
        s_px[2 * k + 1] = 0.5f * (a + b);
        state[2 * k + 1] = near ? kActive : kScalar;
        start[2 * k + 1] = -1.0f;
    }
    const int left = settle_between(W, m, cam, in, W, H, f, o);
    return retry_odd(left, m, raw, s_near, cam, in, inv, nearest, W, H, f, o);
}

}  // namespace deepsea::port_lanes
