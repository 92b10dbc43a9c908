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
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "clones.h"
#include "deepsea/optics/normals.h"
#include "lamp_shadows_lines.h"

namespace deepsea {

namespace {

constexpr int kLanes = 16;
constexpr int kAhead = 8;  ///< steps between a prefetch and its use

/// A sample per lane: valid (1, else 0), depth, shadow coordinates, lamp distance, position.
struct Samples {
    alignas(64) float valid[kLanes], z[kLanes], gf[kLanes], gh[kLanes], gb[kLanes], k[kLanes],
        d1[kLanes], x[kLanes], y[kLanes];
};

/// Each lane's running horizon (lamp_shadows.cpp's Horizon): the edge e (eg, ex, ey, ez, es:
/// shadow coordinate, position, lamp distance), lo, whether e exists (hq) and the step it was
/// swept at (kq).
struct HorizonLanes {
    alignas(64) float eg[kLanes], ex[kLanes], ey[kLanes], ez[kLanes], es[kLanes], lo[kLanes],
        hq[kLanes], kq[kLanes];
};

/// Each lane's second edge e2 (fg, fx, fy, fz, fs as e's) and whether it exists (hq2): it
/// changes only where a new edge does not continue the surface of the last (rarely: on a lit
/// surface every sample continues it), so it is rewritten only at steps where some lane's
/// changes, into the other of two copies (written in place, its selects became masked loads
/// and stores).
struct SecondEdges {
    alignas(64) float fg[kLanes], fx[kLanes], fy[kLanes], fz[kLanes], fs[kLanes], hq2[kLanes];
};

/// Lines i0 .. i_end - 1 (at most kLanes) of the parallel family f.
DEEPSEA_CLONES
void sweep_block(const Family& f, long i0, long i_end, const SweepArrays& s) {
    const int A = f.swap ? s.H : s.W, B = f.swap ? s.W : s.H;
    const int step = f.dir, first = step > 0 ? 0 : A - 1;
    const float R = s.R, kd = float(kDepthDiscontinuity);
    const double slope = f.slope;
    const bool level = slope == 0.0;
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
    SecondEdges e2s[2];
    const SecondEdges* e2p = &e2s[0];  // the current copy; the other is written when it changes
    // Whether some lane of *e2p holds a second edge (hq2 > 0). On a continuous surface none
    // does (each new edge continues the last), and the lit test then skips e2's terms, which
    // cannot change a lane's result where no lane has one. (The penumbra keeps its loop: the
    // same loop without e2 rounded a1 otherwise, fast-math choosing other instructions.)
    bool any_e2 = false;
    {
        SecondEdges& e2 = e2s[0];
        HorizonLanes& h = hz[0];
        for (int j = 0; j < kLanes; ++j) {
            h.eg[j] = e2.fg[j] = -FLT_MAX;
            h.ex[j] = h.ey[j] = h.ez[j] = h.es[j] = 0.0f;
            e2.fx[j] = e2.fy[j] = e2.fz[j] = e2.fs[j] = 0.0f;
            h.lo[j] = FLT_MAX;
            h.hq[j] = e2.hq2[j] = h.kq[j] = 0.0f;
        }
    }
    alignas(64) int shifts[kLanes];  // per lane, whether e2 takes e at this step
    // penumbra_past's bound (R^2 (1 + 2^-10)), where R is far from float's limits
    const float R2m = penumbra_past_scale(R);
    const bool quick = penumbra_past_applies(R);
    alignas(64) float arg[kLanes];
    // the last column's sample and this column's (in turn), the pixel evaluated where it is
    // not the sample (buf[2])
    Samples buf[3] = {};
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
        const SecondEdges& e2 = *e2p;
        HorizonLanes& nh = hz[P ^ 1];
        // Line i's sample in this column is in row i + off, that row's own pixel, but where
        // the lines run exactly between two rows (the row below is then their own); a line
        // is inside the image for i in [i_lo, i_hi].
        // (lines along an image axis, as the demo's lamps give: the same at every step)
        int off = 0, between = 0, i_lo = -1, i_hi = B;
        if (!level) {
            const double base = slope * a;
            off = int(std::floor(base + 0.5));
            between = double(off) - base == 0.5 ? 1 : 0;
            i_lo = int(std::ceil(-1.0 - base));
            i_hi = int(std::floor(double(B) - base));
        }
        const int r_first = line0 + off;
        // (nearly always) the sixteen samples side by side in row a, each lane's pixel its
        // sample's: plain vector loads, and the pixels evaluated are the samples (read from q,
        // not copied into p)
        const bool fast = swap && lanes == kLanes && between == 0 && line0 >= i_lo &&
                          line0 + kLanes - 1 <= i_hi && r_first >= 0 && r_first + kLanes <= B;
        const int o0 = a * W + r_first;
        if (fast) {
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
                q.k[j] = ok ? k : 0.0f;
            }
        } else {
            Samples& p = buf[2];
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
        // every lane is lit, below the horizon's interval or surely past both penumbra edges
        // (nearly every step on a lit floor, whose samples lie within the interval that the
        // samples before them open), nothing is written and the penumbra is not evaluated.
        const Samples& p = fast ? q : buf[2];
        int unlit = 0;
        if (quick && any_e2) {
#pragma omp simd reduction(| : unlit)
            for (int j = 0; j < kLanes; ++j) {
                const float gp = p.gf[j];
                const bool lit = (p.valid[j] <= 0.0f) | (hc.hq[j] <= 0.0f) | (gp < hc.lo[j]);
                const bool past1 = penumbra_past(gp, p.k[j], p.x[j], p.y[j], p.z[j], hc.eg[j],
                                                 hc.ex[j], hc.ey[j], hc.ez[j], hc.es[j], R2m);
                const bool past2 = penumbra_past(gp, p.k[j], p.x[j], p.y[j], p.z[j], e2.fg[j],
                                                 e2.fx[j], e2.fy[j], e2.fz[j], e2.fs[j], R2m);
                const bool seen = lit | (past1 & ((e2.hq2[j] <= 0.0f) | past2));
                unlit |= seen ? 0 : 1;
            }
        } else if (quick) {  // (no lane has e2: the test above without it)
#pragma omp simd reduction(| : unlit)
            for (int j = 0; j < kLanes; ++j) {
                const float gp = p.gf[j];
                const bool lit = (p.valid[j] <= 0.0f) | (hc.hq[j] <= 0.0f) | (gp < hc.lo[j]);
                const bool past1 = penumbra_past(gp, p.k[j], p.x[j], p.y[j], p.z[j], hc.eg[j],
                                                 hc.ex[j], hc.ey[j], hc.ez[j], hc.es[j], R2m);
                unlit |= (lit | past1) ? 0 : 1;
            }
        } else {
#pragma omp simd reduction(| : unlit)
            for (int j = 0; j < kLanes; ++j) {
                const bool lit = (p.valid[j] <= 0.0f) | (hc.hq[j] <= 0.0f) | (p.gf[j] < hc.lo[j]);
                unlit |= lit ? 0 : 1;
            }
        }
        if (unlit && R > 0.0f) {
#pragma omp simd
            for (int j = 0; j < kLanes; ++j) {
                const float gp = p.gf[j];
                const bool lit = (p.valid[j] <= 0.0f) | (hc.hq[j] <= 0.0f) | (gp < hc.lo[j]);
                const float a1 = penumbra_lane(gp, p.k[j], p.x[j], p.y[j], p.z[j], hc.eg[j],
                                               hc.ex[j], hc.ey[j], hc.ez[j], hc.es[j], R);
                const float a2 = penumbra_lane(gp, p.k[j], p.x[j], p.y[j], p.z[j], e2.fg[j],
                                               e2.fx[j], e2.fy[j], e2.fz[j], e2.fs[j], R);
                const bool both = (e2.hq2[j] > 0.0f) & (a1 > -1.0f) & (a2 < a1);
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
            const int pj = fast ? o0 + j : pi[j];
            if (!(fast || pok[j]) || !(p.valid[j] > 0.0f) || arg[j] >= 1.0f) continue;
            const int o = s.out_transposed ? (pj % W) * s.H + pj / W : pj;
            s.out[o] = disc_visible_fraction(arg[j]);
        }
        // the last column's sample joins the horizon, its edge toward this one (Sweep::take).
        // Every field is read into a local before the selects: written as `up ? a[j] : b[j]`,
        // GCC made each select two masked loads and a masked store, which read the stores of
        // the step before (no store forwarding: a third of the sweep's time on AMD).
        const float kp = float(c - 1);
        int any_shift = 0;
#pragma omp simd reduction(| : any_shift)
        for (int j = 0; j < kLanes; ++j) {
            const float eg = hc.eg[j], ex = hc.ex[j], ey = hc.ey[j], ez = hc.ez[j], es = hc.es[j];
            const float lo = hc.lo[j], hq = hc.hq[j], kq = hc.kq[j];
            const float pv = prev.valid[j], zq = prev.z[j], pg = prev.gf[j], ph = prev.gh[j];
            const float b = prev.gb[j], px = prev.x[j], py = prev.y[j], pd = prev.d1[j];
            const float qv = q.valid[j], qz = q.z[j], qg = q.gf[j];
            const bool has = pv > 0.0f;
            const bool chord = (qv > 0.0f) & (std::fabs(zq - qz) <= kd * qz);
            const float ge = chord ? 0.5f * (pg + qg) : ph;
            const bool up = has & (ge > eg);
            const bool mid = has & !up & (ge >= lo);
            const bool goes_on = (hq > 0.0f) & (kp - kq <= 2.0f) & (std::fabs(ez - zq) <= kd * zq);
            const bool shift = up & !goes_on;
            const float lo_min = b < lo ? b : lo;
            const float lo_up = b <= eg ? lo_min : b;
            nh.lo[j] = up ? lo_up : (mid ? lo_min : lo);
            shifts[j] = shift ? 1 : 0;
            any_shift |= shift ? 1 : 0;
            nh.eg[j] = up ? ge : eg;
            nh.ex[j] = up ? px : ex;
            nh.ey[j] = up ? py : ey;
            nh.ez[j] = up ? zq : ez;
            nh.es[j] = up ? pd : es;
            nh.hq[j] = up ? 1.0f : hq;
            nh.kq[j] = up ? kp : kq;
        }
        if (any_shift) {  // e2 takes the old e (hc's) where e moves on to a new surface
            SecondEdges& ne = e2s[e2p == &e2s[0] ? 1 : 0];
            // (each select a blend of bits: written as `shift ? a : b`, GCC loaded a and b
            // with masked loads)
            const auto blend = [](int m, float a, float b) __attribute__((always_inline)) {
                std::uint32_t ua, ub;
                std::memcpy(&ua, &a, 4);
                std::memcpy(&ub, &b, 4);
                const std::uint32_t u = (ua & std::uint32_t(m)) | (ub & ~std::uint32_t(m));
                float r;
                std::memcpy(&r, &u, 4);
                return r;
            };
            int has_e2 = 0;
#pragma omp simd reduction(| : has_e2)
            for (int j = 0; j < kLanes; ++j) {
                const int m = -shifts[j];  // all bits where e2 takes e
                ne.fg[j] = blend(m, hc.eg[j], e2.fg[j]);
                ne.fx[j] = blend(m, hc.ex[j], e2.fx[j]);
                ne.fy[j] = blend(m, hc.ey[j], e2.fy[j]);
                ne.fz[j] = blend(m, hc.ez[j], e2.fz[j]);
                ne.fs[j] = blend(m, hc.es[j], e2.fs[j]);
                const float hq2 = blend(m, hc.hq[j], e2.hq2[j]);
                ne.hq2[j] = hq2;
                has_e2 |= hq2 > 0.0f ? 1 : 0;
            }
            e2p = &ne;
            any_e2 = has_e2 != 0;
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

void sweep_parallel_lines(const std::vector<LampShadows::ParallelSweep>& sweeps) {
    // block b of the whole list is block b - first[l] of lamp l
    std::vector<long> first(sweeps.size() + 1, 0);
    for (std::size_t l = 0; l < sweeps.size(); ++l) {
        const Family& f = sweeps[l].f;
        const long blocks = f.i_max < f.i_min ? 0 : (f.i_max - f.i_min + kLanes) / kLanes;
        first[l + 1] = first[l] + blocks;
    }
    tbb::parallel_for(0L, first.back(), [&](long b) {
        const std::size_t l =
            std::size_t(std::upper_bound(first.begin(), first.end(), b) - first.begin()) - 1;
        const Family& f = sweeps[l].f;
        const long i0 = f.i_min + (b - first[l]) * kLanes;
        sweep_block(f, i0, std::min(i0 + kLanes, f.i_max + 1), sweeps[l].s);
    });
}

}  // namespace deepsea
