// The sweep of a family of parallel epipolar lines (a lamp in the camera's plane z = 0, as the
// demo's two, or an epipole far outside the image) with eight neighbouring lines in the lanes of
// a vector (docs/snow-shadows.md, "Sweep"). Compiled with -ffast-math -fopenmp-simd like
// lamp_shadows.cpp; open water is -FLT_MAX there, never NaN or inf.
//
// The per-line work is lamp_shadows.cpp's (Sweep::visible, Sweep::take), written as selects: at
// each step along the lines the eight lines' samples are gathered into small arrays, tested
// against the eight horizons and added to them in loops over the lanes, which GCC vectorises.
// The lanes' lines are independent, so the result is each line's own, at any block size and
// thread count.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <type_traits>

#include "clones.h"
#include "deepsea/optics/normals.h"
#include "lamp_shadows_lines.h"

namespace deepsea {

namespace {

constexpr int kLanes = 16;
constexpr int kAhead = 8;  ///< steps between a prefetch and its use

/// The penumbra's argument at P (shadow coordinate gp, scale k, position p) of the edge at
/// (eg, e, es = its distance to the lamp): lamp_shadows.cpp's penumbra_at without its
/// branches. Where that returns 1 (the whole disc seen) this is at least 1, which counts the
/// same; an edge point at P itself (never swept: edges are other pixels') would give +-1 there
/// and a large +-value here.
inline float penumbra_lane(float gp, float k, float px, float py, float pz, float eg, float ex,
                           float ey, float ez, float es, float R) {
    const float delta = gp - eg;
    const float dx = px - ex, dy = py - ey, dz = pz - ez;
    const float d2 = dx * dx + dy * dy + dz * dz;
    return delta * k * es / (R * std::sqrt(d2 > 1e-30f ? d2 : 1e-30f));
}

/// A sample per lane: valid (1, else 0), depth, shadow coordinates, lamp distance, position.
struct Samples {
    alignas(64) float valid[kLanes], z[kLanes], gf[kLanes], gh[kLanes], gb[kLanes], k[kLanes],
        d1[kLanes], x[kLanes], y[kLanes];
};

/// Each lane's running horizon (lamp_shadows.cpp's Horizon): the edges e (eg, ex, ey, ez, es:
/// shadow coordinate, position, lamp distance) and e2 (fg, ...), lo, whether e and e2 exist
/// (hq, hq2) and the step e was swept at (kq).
struct HorizonLanes {
    alignas(64) float eg[kLanes], ex[kLanes], ey[kLanes], ez[kLanes], es[kLanes], fg[kLanes],
        fx[kLanes], fy[kLanes], fz[kLanes], fs[kLanes], lo[kLanes], hq[kLanes], hq2[kLanes],
        kq[kLanes];
};

/// Lines i0 .. i_end - 1 (at most kLanes) of the parallel family f.
DEEPSEA_CLONES
void sweep_block(const Family& f, long i0, long i_end, const SweepArrays& s) {
    const int A = f.swap ? s.H : s.W, B = f.swap ? s.W : s.H;
    const int step = f.dir, first = step > 0 ? 0 : A - 1;
    const float R = s.R, kd = float(kDepthDiscontinuity);
    const double slope = f.slope;
    const bool swap = f.swap;
    const int W = s.W, line0 = int(i0), lanes = int(i_end - i0);
    const float *zz = s.z, *rx = s.rx, *ry = s.ry;
    const RowParams prm = s.prm;
    const float su = prm.ex, sv = prm.ey;  // the sweep's direction (parallel lines)
    const float zfar = float(kFarDepth);
    // each lane's horizon (lamp_shadows.cpp's Horizon), read from one copy and written to the
    // other at each step, so that its update is a select and a plain store (kept in one array,
    // GCC made it masked stores, slow on AMD)
    HorizonLanes hz[2];
    {
        HorizonLanes& h = hz[0];
        for (int j = 0; j < kLanes; ++j) {
            h.eg[j] = h.fg[j] = -FLT_MAX;
            h.ex[j] = h.ey[j] = h.ez[j] = h.es[j] = h.fx[j] = h.fy[j] = h.fz[j] = h.fs[j] = 0.0f;
            h.lo[j] = FLT_MAX;
            h.hq[j] = h.hq2[j] = h.kq[j] = 0.0f;
        }
    }
    alignas(64) float arg[kLanes];
    // the last column's sample and this column's (in turn), the pixel evaluated
    Samples buf[2] = {}, p{};
    // per lane: the sample's pixel index and column, row (0 where none: a safe address; the
    // sample is then marked invalid), and the pixel evaluated where it is another (see below)
    alignas(64) int qi[kLanes], qu[kLanes], qv[kLanes], qok[kLanes], pi[kLanes], pok[kLanes];
    // One step along the lines, column c (parity P = c & 1 picks the buffers: a constant, so
    // that their addresses are too; with c & 1 in the loop GCC recomputed some 26 array
    // addresses at each step).
    const auto column = [&](int c, auto parity) __attribute__((always_inline)) {
        constexpr int P = decltype(parity)::value;
        const int a = first + c * step;
        Samples& q = buf[P];
        const Samples& prev = buf[P ^ 1];
        const HorizonLanes& hc = hz[P];
        HorizonLanes& nh = hz[P ^ 1];
        // Line i's sample in this column is in row i + off, that row's own pixel, but where
        // the lines run exactly between two rows (the row below is then their own); a line
        // is inside the image for i in [i_lo, i_hi].
        const double base = slope * a;
        const int off = int(std::floor(base + 0.5));
        const int between = double(off) - base == 0.5 ? 1 : 0;
        const int i_lo = int(std::ceil(-1.0 - base)), i_hi = int(std::floor(double(B) - base));
        const int r_first = line0 + off;
        if (swap && lanes == kLanes && between == 0 && line0 >= i_lo &&
            line0 + kLanes - 1 <= i_hi && r_first >= 0 && r_first + kLanes <= B) {
            // (nearly always) the eight samples side by side in row a: plain vector loads
            const int o0 = a * W + r_first;
            // the depth a few steps ahead (the lanes read 32 bytes a row, rows apart)
            // (both cache lines the sixteen depths may span)
            if (c + kAhead < A) {
                __builtin_prefetch(zz + o0 + kAhead * step * W);
                __builtin_prefetch(zz + o0 + kAhead * step * W + kLanes - 1);
            }
            const float ya = ry[a];
            const float* rxa = rx + r_first;
#pragma omp simd
            for (int j = 0; j < kLanes; ++j) {
                const int o = o0 + j;
                const float zraw = zz[o];
                const bool ok = (zraw > 0.0f) & (zraw < zfar);
                const float z = ok ? zraw : 0.0f;
                float g, h, b, k, d;
                sample_terms(z, rxa[j], ya, su, sv, prm, g, h, b, k, d);
                q.valid[j] = ok ? 1.0f : 0.0f;
                q.z[j] = ok ? z : 1.0f;
                q.gf[j] = ok ? g : 0.0f;
                q.gh[j] = ok ? h : 0.0f;
                q.gb[j] = ok ? b : 0.0f;
                q.d1[j] = ok ? d : 0.0f;
                q.x[j] = ok ? rxa[j] * z : 0.0f;
                q.y[j] = ok ? ya * z : 0.0f;
                p.valid[j] = q.valid[j];
                p.gf[j] = q.gf[j];
                p.z[j] = q.z[j];
                p.k[j] = ok ? k : 0.0f;
                p.x[j] = q.x[j];
                p.y[j] = q.y[j];
                pi[j] = o;
                pok[j] = 1;
            }
        } else {
            bool other = false;  // whether any lane evaluates a pixel other than its sample
#pragma omp simd reduction(| : other)
            for (int j = 0; j < kLanes; ++j) {
                const int i = line0 + j;
                const bool in = (j < lanes) & (i >= i_lo) & (i <= i_hi);
                const int r0 = i + off, r = r0 - between;
                const bool okq = in & (r0 >= 0) & (r0 < B), okp = in & (r >= 0) & (r < B);
                const int u = okq ? (swap ? r0 : a) : 0, v = okq ? (swap ? a : r0) : 0;
                qu[j] = u;
                qv[j] = v;
                qi[j] = v * W + u;
                qok[j] = okq;
                pi[j] = (swap ? a : r) * W + (swap ? r : a);
                pok[j] = okp;
                other |= (okp != okq) | (okp & (r != r0));
            }
#pragma omp simd
            for (int j = 0; j < kLanes; ++j) {
                const int o = qi[j];
                const float zraw = zz[o], xr = rx[qu[j]], yr = ry[qv[j]];
                const bool ok = (qok[j] != 0) & (zraw > 0.0f) & (zraw < zfar);
                const float z = ok ? zraw : 0.0f;
                float g, h, b, k, d;
                sample_terms(z, xr, yr, su, sv, prm, g, h, b, k, d);
                q.valid[j] = ok ? 1.0f : 0.0f;
                q.z[j] = ok ? z : 1.0f;
                q.gf[j] = ok ? g : 0.0f;
                q.gh[j] = ok ? h : 0.0f;
                q.gb[j] = ok ? b : 0.0f;
                q.d1[j] = ok ? d : 0.0f;
                q.x[j] = ok ? xr * z : 0.0f;
                q.y[j] = ok ? yr * z : 0.0f;
                p.valid[j] = q.valid[j];
                p.gf[j] = q.gf[j];
                p.z[j] = q.z[j];
                p.k[j] = ok ? k : 0.0f;
                p.x[j] = q.x[j];
                p.y[j] = q.y[j];
            }
            for (int j = 0; other && j < kLanes; ++j) {
                if (pok[j] && qok[j] && pi[j] == qi[j]) continue;
                const int o = pok[j] ? pi[j] : 0;
                const float zraw = pok[j] ? zz[o] : 0.0f;
                const bool ok = has_surface(zraw);
                const float z = ok ? zraw : 0.0f;
                const int u = o % W, v = o / W;
                float g, h, b, k, d;
                sample_terms(z, rx[u], ry[v], su, sv, prm, g, h, b, k, d);
                p.valid[j] = ok ? 1.0f : 0.0f;
                p.gf[j] = ok ? g : 0.0f;
                p.z[j] = ok ? z : 1.0f;
                p.k[j] = ok ? k : 0.0f;
                p.x[j] = ok ? rx[u] * z : 0.0f;
                p.y[j] = ok ? ry[v] * z : 0.0f;
            }
        }
        // P's visibility under the horizon (Sweep::visible); the disc's fraction after. Where
        // every lane is lit (most steps) nothing is written: the penumbra is not evaluated.
        int unlit = 0;
#pragma omp simd reduction(| : unlit)
        for (int j = 0; j < kLanes; ++j) {
            const bool lit = (p.valid[j] <= 0.0f) | (hc.hq[j] <= 0.0f) | (p.gf[j] < hc.lo[j]);
            unlit |= lit ? 0 : 1;
        }
        if (unlit && R > 0.0f) {
#pragma omp simd
            for (int j = 0; j < kLanes; ++j) {
                const float gp = p.gf[j];
                const bool lit = (p.valid[j] <= 0.0f) | (hc.hq[j] <= 0.0f) | (gp < hc.lo[j]);
                const float a1 = penumbra_lane(gp, p.k[j], p.x[j], p.y[j], p.z[j], hc.eg[j],
                                               hc.ex[j], hc.ey[j], hc.ez[j], hc.es[j], R);
                const float a2 = penumbra_lane(gp, p.k[j], p.x[j], p.y[j], p.z[j], hc.fg[j],
                                               hc.fx[j], hc.fy[j], hc.fz[j], hc.fs[j], R);
                const bool both = (hc.hq2[j] > 0.0f) & (a1 > -1.0f) & (a2 < a1);
                const float m = both ? a2 : a1;
                arg[j] = lit ? 1.0f : m;
            }
        } else if (unlit) {
#pragma omp simd
            for (int j = 0; j < kLanes; ++j) {
                const float gp = p.gf[j];
                const bool lit = (p.valid[j] <= 0.0f) | (hc.hq[j] <= 0.0f) | (gp < hc.lo[j]);
                arg[j] = (lit | (gp > hc.eg[j])) ? 1.0f : -1.0f;
            }
        }
        // (the image is filled with 1: only shadowed pixels are written)
        float least = 1.0f;  // (arg is 1 where no pixel is evaluated)
        if (unlit) {
#pragma omp simd reduction(min : least)
            for (int j = 0; j < kLanes; ++j) least = arg[j] < least ? arg[j] : least;
        }
        for (int j = 0; least < 1.0f && j < kLanes; ++j) {
            if (!pok[j] || !(p.valid[j] > 0.0f) || arg[j] >= 1.0f) continue;
            const int o = s.out_transposed ? (pi[j] % W) * s.H + pi[j] / W : pi[j];
            s.out[o] = disc_visible_fraction(arg[j]);
        }
        // the last column's sample joins the horizon, its edge toward this one (Sweep::take)
        const float kp = float(c - 1);
#pragma omp simd
        for (int j = 0; j < kLanes; ++j) {
            const bool has = prev.valid[j] > 0.0f;
            const float zq = prev.z[j];
            const bool chord = (q.valid[j] > 0.0f) & (std::fabs(zq - q.z[j]) <= kd * q.z[j]);
            const float ge = chord ? 0.5f * (prev.gf[j] + q.gf[j]) : prev.gh[j];
            const float b = prev.gb[j];
            const float eg = hc.eg[j], lo = hc.lo[j], hq = hc.hq[j];
            const bool up = has & (ge > eg);
            const bool mid = has & !up & (ge >= lo);
            const bool goes_on =
                (hq > 0.0f) & (kp - hc.kq[j] <= 2.0f) & (std::fabs(hc.ez[j] - zq) <= kd * zq);
            const bool shift = up & !goes_on;
            const float lo_min = b < lo ? b : lo;
            const float lo_up = b <= eg ? lo_min : b;
            nh.lo[j] = up ? lo_up : (mid ? lo_min : lo);
            nh.fg[j] = shift ? eg : hc.fg[j];
            nh.fx[j] = shift ? hc.ex[j] : hc.fx[j];
            nh.fy[j] = shift ? hc.ey[j] : hc.fy[j];
            nh.fz[j] = shift ? hc.ez[j] : hc.fz[j];
            nh.fs[j] = shift ? hc.es[j] : hc.fs[j];
            nh.hq2[j] = shift ? hq : hc.hq2[j];
            nh.eg[j] = up ? ge : eg;
            nh.ex[j] = up ? prev.x[j] : hc.ex[j];
            nh.ey[j] = up ? prev.y[j] : hc.ey[j];
            nh.ez[j] = up ? zq : hc.ez[j];
            nh.es[j] = up ? prev.d1[j] : hc.es[j];
            nh.hq[j] = up ? 1.0f : hq;
            nh.kq[j] = up ? kp : hc.kq[j];
        }
    };
    int c = 0;
    for (; c + 1 < A; c += 2) {
        column(c, std::integral_constant<int, 0>{});
        column(c + 1, std::integral_constant<int, 1>{});
    }
    if (c < A) column(c, std::integral_constant<int, 0>{});
}

}  // namespace

void sweep_parallel_lines(const Family& f, const SweepArrays& s) {
    if (f.i_max < f.i_min) return;
    const long blocks = (f.i_max - f.i_min + kLanes) / kLanes;
    tbb::parallel_for(0L, blocks, [&](long k) {
        const long i0 = f.i_min + k * kLanes;
        sweep_block(f, i0, std::min(i0 + kLanes, f.i_max + 1), s);
    });
}

}  // namespace deepsea
