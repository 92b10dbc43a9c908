#pragma once
// Internal: what the port's row kernels share (port_warp.cpp, port_march_rows.cpp): the
// vectorised march's lane states and scratch, and the hit's taps. Both files are compiled with
// -fopenmp-simd, -ffp-contract=off and -fno-trapping-math, not fast-math (see CMakeLists.txt), so
// that their lanes do the scalar march's float arithmetic.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "deepsea/runtime/port_rays.h"
#include "float4.h"
#include "port_warp.h"

// (Float8 values live in registers inside the kernels: no call passes one, so GCC's note that
// AVX changes the ABI of such calls does not apply to their generic clones)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace deepsea::port_lanes {

/// What the vectorised march found for a ray.
enum FastState : int {
    kActive = 0,    ///< bracketed, refining
    kSurface = 1,   ///< the crossing at s, on one surface (as the scalar march's continuous hit)
    kScalar = 2,    ///< anything else: the scalar march (march_port_ray) decides
    kOpen = 3,      ///< in front of the surface over its whole view, to its vanishing point
    kUnseen = 4,    ///< in front over its whole view, which ends before the vanishing point
    kMarching = 5,  ///< in front of the surface so far, stepping toward the vanishing point
};

/// The hit point's x or y from where it projects in the input (pixel p, centre c, focal length
/// f as k = 1 / f) and its planar depth z: the point on the ray at depth z projects there, so this
/// is ray origin + t direction, without reading the ray (docs/port-speed.md: within 1.5e-7 z of
/// the double trace's point).
inline float back_project(float p, float c, float k, float z) { return ((p - c) * k) * z; }

/// The input camera's centre and inverse focal lengths in float, for back_project.
struct Pinhole {
    float cx, cy, kx, ky;
    explicit Pinhole(const Camera& c)
        : cx(float(c.cx)), cy(float(c.cy)), kx(float(1.0 / c.fx)), ky(float(1.0 / c.fy)) {}
};

/// The march's rate (PortMarch::rate, max(|du|, |dv|) in double rounded to float) from du and dv
/// in float: rounding keeps the order, so this is the same float.
inline float rate_of(float du, float dv) {
    const float a = std::fabs(du), b = std::fabs(dv);
    return a < b ? b : a;
}

/// The rows' scratch, one a thread, sized for a row: the vectorised march's state (fast_march,
/// settle_hits).
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

/// The march of optics' march_port_ray for the n rays of m (port_march_rows.cpp): their
/// brackets of the first crossing (kActive) where it takes at most a few steps over one surface,
/// kOpen, kUnseen, else kScalar; each ray's start in f.start.
void fast_march(int n, PortRays::MarchRow m, const float* inv, const float* nearest, int W, int H,
                float s_near, MarchScratch& f);

/// The Illinois step of the n rays that fast_march bracketed (kActive) and the hits it settles
/// on one surface (kSurface; port_warp.cpp): their points, normals, colour and mask into o, the
/// others' zeros (kScalar where the step does not settle). Returns the number left to the scalar
/// march.
int settle_hits(int n, PortRays::MarchRow m, Pinhole cam, const float* in, int W, int H,
                MarchScratch& f, const PortRow& o);

/// The four lanes of a Float8: its first (lo) or its last (hi).
inline Float4 low4(Float8 v) { return __builtin_shufflevector(v, v, 0, 1, 2, 3); }
inline Float4 high4(Float8 v) { return __builtin_shufflevector(v, v, 4, 5, 6, 7); }
/// Lane k of each half of v in that half (one in-lane permute).
template <int k>
inline Float8 splat_halves(Float8 v) {
    return __builtin_shufflevector(v, v, k, k, k, k, k + 4, k + 4, k + 4, k + 4);
}

/// The hit's taps of lane u: one 8-float load a tap from the interleaved surface at p (the
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

/// The Illinois method's step between a bracket's ends (a in front of the surface, b behind):
/// regula falsi, bisection where it falls outside. The same float arithmetic as optics'
/// Marcher::refine's first step.
inline float illinois_step(float a_s, float a_h, float b_s, float b_h) {
    const float s = (a_s * b_h - b_s * a_h) / (b_h - a_h);
    return s < a_s && s > b_s ? s : 0.5f * (a_s + b_s);
}

/// Where taps_at reads the position (hu, hv) (clamped to the pixel centres; W, H >= 2): at, the
/// interleaved surface's offset of its 2 x 2 pixels, their weights w[0..3] (0 where !active),
/// and the position's fractions in the cell.
inline void place_taps(float hu, float hv, int W, int H, bool active, int& at, float* w, float& fu,
                       float& fv) {
    float pu = hu > 0.0f ? hu : 0.0f, pv = hv > 0.0f ? hv : 0.0f;
    pu = pu < float(W - 1) ? pu : float(W - 1);
    pv = pv < float(H - 1) ? pv : float(H - 1);
    const int x0 = std::min(int(pu), W - 2), y0 = std::min(int(pv), H - 2);
    fu = pu - float(x0);
    fv = pv - float(y0);
    at = (y0 * W + x0) * kPortSurfaceChannels;
    w[0] = active ? (1 - fu) * (1 - fv) : 0.0f;
    w[1] = active ? fu * (1 - fv) : 0.0f;
    w[2] = active ? (1 - fu) * fv : 0.0f;
    w[3] = active ? fu * fv : 0.0f;
}

/// Whether a probe at s with the taps' inverse depth iz, between four pixels whose least and
/// largest inverse depths are lo and hi, is the march's hit: on one surface and on the surface
/// to the float march's tolerance (optics' Marcher::refine); one_surface the first half.
inline bool one_surface(float lo, float hi) {
    return (lo > 0.0f) & (hi - lo <= float(kDepthDiscontinuity) * lo);
}
inline bool settles(float lo, float hi, float s, float iz) {
    return one_surface(lo, hi) & (std::fabs(s - iz) <= kPortHitToleranceFloat * (s + iz));
}

/// The hit point at inverse depth s, projecting to (hu, hv) in the input, on the ray whose
/// origin has planar depth oz and direction dz: its camera-frame x, y, z and path t from the
/// port, back-projected from where it projects (back_project).
inline void hit_point(float hu, float hv, float s, float oz, float dz, const Pinhole& cam, float& x,
                      float& y, float& z, float& t) {
    z = 1.0f / s;
    t = (z - oz) / dz;
    x = back_project(hu, cam.cx, cam.kx, z);
    y = back_project(hv, cam.cy, cam.ky, z);
}

/// The taps' normal sums (Nx, Ny, Nz) made a unit vector (0 where they are 0).
inline void unit_normal(float Nx, float Ny, float Nz, float& nx, float& ny, float& nz) {
    const float len = std::sqrt(Nx * Nx + Ny * Ny + Nz * Nz);
    const float inv = len > 0.0f ? 1.0f / len : 0.0f;
    nx = Nx * inv;
    ny = Ny * inv;
    nz = Nz * inv;
}

/// The taps of n pixels (settle_taps at in + at[u]), the colour into J (3 a pixel): prefetched
/// kAhead pixels ahead, the loop split where the prefetch ends, so that no pixel tests whether it
/// prefetches; the colour stored four floats at a time, the fourth overwritten by the next
/// pixel's red, but for the last pixel, whose fourth would lie beyond the row.
__attribute__((always_inline)) inline void taps_row(int n, const float* in, const int* at,
                                                    std::size_t row, float* w, float* lo_z,
                                                    float* hi_z, float* J) {
    constexpr int kAhead = 16;
    const int ahead_end = n > kAhead ? n - kAhead : 0;
    for (int u = 0; u < ahead_end; ++u) {
        __builtin_prefetch(in + at[u + kAhead]);
        __builtin_prefetch(in + at[u + kAhead] + row);
        store4(J + 3 * u, settle_taps(in + at[u], row, u, w, lo_z, hi_z));
    }
    for (int u = ahead_end; u < n - 1; ++u)
        store4(J + 3 * u, settle_taps(in + at[u], row, u, w, lo_z, hi_z));
    if (n > 0) {
        const Float4 j = settle_taps(in + at[n - 1], row, n - 1, w, lo_z, hi_z);
        for (int k = 0; k < 3; ++k) J[3 * (n - 1) + k] = j[k];
    }
}

}  // namespace deepsea::port_lanes
