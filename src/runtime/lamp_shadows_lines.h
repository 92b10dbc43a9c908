#pragma once
// Internal to lamp_shadows*.cpp: a lamp's epipolar lines (families of them) and the per-pixel
// arrays the sweep reads, shared by the scalar sweep (lamp_shadows.cpp) and the sweep of
// parallel lines in vector lanes (lamp_shadows_lanes.cpp).

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

/// One lamp's per-pixel inputs (the frame's row-major layout) and its visibility image: the
/// surface's shadow coordinate gf (-FLT_MAX: open water), its pixel's far edge gh and that edge
/// `thickness` deeper gb, the penumbra's scale k, the lamp distance d1, the planar depth z, the
/// rays' x per column and y per row; R the lamp's radius.
struct SweepArrays {
    const float *gf, *gh, *gb, *k, *d1, *z, *rx, *ry;
    float* out;
    int W, H;
    float R;
};

/// Sweeps the parallel family `f` (not radial) over the image, eight neighbouring lines at a
/// time in the lanes of a vector: the same horizon, test and update per line as the scalar
/// sweep of lamp_shadows.cpp (docs/snow-shadows.md, "Sweep"), its branches as selects. Blocks
/// of lines in parallel; each pixel is written by its own line only.
void sweep_parallel_lines(const Family& f, const SweepArrays& s);

}  // namespace deepsea
