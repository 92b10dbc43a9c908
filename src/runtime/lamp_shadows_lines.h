#pragma once
// Internal to lamp_shadows*.cpp: a lamp's epipolar lines (families of them) and the per-pixel
// arrays the sweep reads, shared by the scalar sweep (lamp_shadows.cpp) and the sweep of
// parallel lines in vector lanes (lamp_shadows_lanes.cpp).

#include <cfloat>
#include <cmath>
#include <vector>

#include "deepsea/runtime/lamp_shadows.h"

namespace deepsea {

/// One family of lines in image coordinates (a, b): (u, v), or (v, u) where `swap`.
struct Family {
    bool swap = false;
    bool radial = false;
    int sigma = 1;          ///< radial: the half (a - ea has this sign) the fan covers
    int dir = 1;            ///< the sweep's step along a
    double ea = 0, eb = 0;  ///< radial: the epipole
    double m = 1;           ///< radial: slope of line i is i / m
    double slope = 0;       ///< parallel: b = i + slope * a
    long i_min = 0, i_max = -1;
};

constexpr double kFarEpipole = 1e6;  // px from the image: lines taken as parallel beyond

inline long round_index(double x) { return long(std::floor(x + 0.5)); }

struct LampShadows::Lines {
    std::vector<Family> families;
    int width = 0, height = 0;

    /// The family and line that pixel (u, v) belongs to.
    void locate(int u, int v, int& family, long& line) const {
        const Family& f0 = families[0];
        if (!f0.radial) {
            const double a = f0.swap ? v : u, b = f0.swap ? u : v;
            family = 0;
            line = round_index(b - f0.slope * a);
            return;
        }
        const double dx = u - (f0.swap ? f0.eb : f0.ea), dy = v - (f0.swap ? f0.ea : f0.eb);
        double qa, qb;
        if (dx >= std::fabs(dy)) {
            family = 0, qa = dx, qb = dy;
        } else if (-dx >= std::fabs(dy)) {
            family = 1, qa = dx, qb = dy;
        } else if (dy > 0) {
            family = 2, qa = dy, qb = dx;
        } else {
            family = 3, qa = dy, qb = dx;
        }
        line = qa == 0.0 ? 0 : round_index(families[family].m * qb / qa);
    }
    double line_b(const Family& f, long i, double a) const {
        return f.radial ? f.eb + (double(i) / f.m) * (a - f.ea) : double(i) + f.slope * a;
    }
};

/// What sample_terms needs of the lamp and the sweep: the camera's fx, fy; the sweep's
/// direction (ex, ey: the epipole, radial lines, with `outward`; the step, parallel lines);
/// the lamp's unit vector a, distance dl and position l; the thickness t.
struct RowParams {
    float fx, fy, ex, ey, outward, ax, ay, az, dl, lx, ly, lz, t;
    bool radial;
};

/// A pixel's terms for the lamp (planar depth zr, 0 for open water; ray (rx, ry); the sweep's
/// direction (su, sv) there): the shadow coordinate of the surface (gf), and, as an occluder,
/// of its pixel's far edge along the sweep (gh) and of that edge `t` deeper (gb), -FLT_MAX
/// for open water; the penumbra's scale k and the lamp distance d1. The edge is half a pixel
/// further along the sweep, (su, sv) scaled so that its larger component is 1/2: where a
/// pixel's surface ends is unknown, and between two pixels is the least biased guess (without
/// it every shadow edge lay half a pixel short). Branch-free (masks as floats, as
/// kernels.cpp's), for vectorised loops.
[[gnu::always_inline]] inline void sample_terms(float zr, float rxu, float ry, float su, float sv,
                                                const RowParams& p, float& gf, float& gh, float& gb,
                                                float& k, float& d1) {
    const float ax = p.ax, ay = p.ay, az = p.az, dl = p.dl;
    const float surf = zr > 0.0f ? 1.0f : 0.0f, none = (surf - 1.0f) * FLT_MAX;
    const float zs = zr > 0.0f ? zr : 1.0f;
    const float px = rxu * zs, py = ry * zs;
    const float cx = py * az - zs * ay, cy = zs * ax - px * az, cz = px * ay - py * ax;
    const float c2r = cx * cx + cy * cy + cz * cz;
    const float c2 = c2r > 1e-30f ? c2r : 1e-30f;  // (no std::max: its reference stays scalar)
    const float pa = px * ax + py * ay + zs * az;
    const float dx = p.lx - px, dy = p.ly - py, dz = p.lz - zs;
    const float d = std::sqrt(dx * dx + dy * dy + dz * dz);
    gf = surf * ((dl - pa) / std::sqrt(c2)) + none;
    k = c2 / d;
    d1 = d;
    // the pixel's far edge
    const float mu = std::fabs(su) > std::fabs(sv) ? std::fabs(su) : std::fabs(sv);
    const float m = mu > 1e-20f ? mu : 1e-20f;
    const float qx = (rxu + 0.5f * su / (m * p.fx)) * zs, qy = (ry + 0.5f * sv / (m * p.fy)) * zs;
    const float ex2 = qy * az - zs * ay, ey2 = zs * ax - qx * az, ez2 = qx * ay - qy * ax;
    const float e2r = ex2 * ex2 + ey2 * ey2 + ez2 * ez2;
    const float e2 = e2r > 1e-30f ? e2r : 1e-30f;
    const float qa = qx * ax + qy * ay + zs * az;
    const float inv = 1.0f / std::sqrt(e2);
    // deeper by t along the viewing ray: Q (z + t) / z, so Q x a and Q . a scale alike
    const float s = (zs + p.t) / zs;
    gh = surf * ((dl - qa) * inv) + none;
    gb = surf * ((dl - s * qa) * inv / s) + none;
}

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

/// Whether penumbra_lane(gp, k, p, e, R) is surely at least 1 (the whole disc seen past the
/// edge), without its square root and division: where its numerator's square is at least
/// R^2 d2 (1 + 2^-10) = R2m d2, h is at least 1 + 2^-11 in exact arithmetic, far above the
/// rounding of either form and the vector square root's and reciprocal's error (a few 1e-7).
/// num is clamped down and d2 up (to 1e15 and 1e-20: either only makes the test harder), so
/// that num^2 is finite and R2m d2 normal for R in [1e-5, 1e5] m; where R2m d2 overflows the
/// test fails.
inline bool penumbra_past(float gp, float k, float px, float py, float pz, float eg, float ex,
                          float ey, float ez, float es, float R2m) {
    const float num_raw = (gp - eg) * k * es;
    const float num = num_raw < 1e15f ? num_raw : 1e15f;
    const float dx = px - ex, dy = py - ey, dz = pz - ez;
    const float d2_raw = dx * dx + dy * dy + dz * dz;
    const float d2 = d2_raw > 1e-20f ? d2_raw : 1e-20f;
    return (num > 0.0f) & (num * num >= R2m * d2);
}

/// penumbra_past's R2m for a lamp of radius R (m).
inline float penumbra_past_scale(float R) { return R * R * (1.0f + 1.0f / 1024.0f); }

/// Whether penumbra_past holds for a lamp of radius R (m) (else the penumbra is evaluated).
inline bool penumbra_past_applies(float R) { return R >= 1e-5f && R <= 1e5f; }

/// One lamp's inputs for the sweep of parallel lines and its visibility image (filled with 1
/// before: only shadowed pixels are written): the frame's planar depth, the rays' x per column
/// and y per row, the lamp's radius R and sample_terms' parameters; `out_transposed`: the
/// visibility image is the transpose of the depth's (H x W: the sweep runs on the transposed
/// frame and writes the frame's own image).
struct SweepArrays {
    const float *z, *rx, *ry;
    float* out;
    int W, H;
    float R;
    RowParams prm;
    bool out_transposed;
};

struct LampShadows::ParallelSweep {
    Family f;
    SweepArrays s;
};

/// Sweeps each lamp's parallel family `f` (not radial) over its image, sixteen neighbouring
/// lines at a time in the lanes of vectors: the same horizon, test and update per line as the
/// scalar sweep of lamp_shadows.cpp (docs/snow-shadows.md, "Sweep"), its branches as selects,
/// each sample's terms computed as it is swept. The blocks of lines of every lamp in one
/// parallel loop (a lamp's 25 blocks at 800x800 split 13 to 12 over two threads; the two lamps'
/// 50, evenly); each pixel is written by its own line only.
void sweep_parallel_lines(const std::vector<LampShadows::ParallelSweep>& sweeps);

}  // namespace deepsea
