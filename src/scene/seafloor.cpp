// Procedural seafloor: the height field and ray marching (flight.cpp renders frames with it;
// the albedo texture is seafloor_albedo.cpp). The parameters are in seafloor_parts.h.

#include "deepsea/scene/seafloor.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "noise.h"
#include "seafloor_parts.h"

namespace deepsea {

using namespace scene_detail;

namespace {

/// Bound on sqrt(1 - q^2) |grad q^2| * b over a lumpy ellipse with semi-minor axis b, from
/// its expression in normalised coordinates (u/a, v/b): times 1.5 H / b it bounds the slope
/// of the bump profile H (1 - q^2)^1.5.
double lumpy_profile_slope() {
    const double lump_slope = fbm_slope(kLumpOctaves) * kLumpFrequency;
    const double r_end = kOutline;
    double best = 0.0;
    for (int i = 0; i <= 2000; ++i) {
        const double r = r_end * i / 2000.0;
        const double inside = std::max(0.0, 1.0 - r * r * kLumpLo);
        best = std::max(best, std::sqrt(inside) * (2.0 * r * kLumpHi + r * r * kLump * lump_slope));
    }
    return best * 1.02;  // the maximum may fall between samples
}

}  // namespace

Seafloor::Seafloor(std::uint64_t seed, double relief) : m_relief(relief) {
    for (int i = 0; i < kLayerCount; ++i) m_salt[i] = layer_salt(seed, std::uint64_t(i));
    // Ripple crests run in a seed-dependent direction; a unit vector from two hashed values,
    // normalised with sqrt only (no trigonometry, see noise.h).
    const double kx = cell_unit(m_salt[kRippleDirLayer], 0) - 0.5;
    const double ky = cell_unit(m_salt[kRippleDirLayer], 1) - 0.5;
    const double n = std::sqrt(kx * kx + ky * ky);
    if (n > 1e-3) {
        m_ripple_kx = kx / n;
        m_ripple_ky = ky / n;
    }

    const double large_max = kLargeAmplitude * kNoiseMax * fbm_amplitude(kLargeOctaves);
    const double micro_max = kMicroAmplitude * kNoiseMax * fbm_amplitude(kMicroOctaves);
    const double bump_max = kNoduleHeightMax * kMaxRadius;
    m_detail_below = relief * (0.5 * kRippleHeight + micro_max);
    m_detail_above = relief * (0.5 * kRippleHeight + micro_max + bump_max);
    m_min_height = -relief * large_max - m_detail_below;
    m_max_height = relief * large_max + m_detail_above;

    // Slope bounds: each term's amplitude times the gradient bound of its noise.
    const double large_slope = kLargeAmplitude * fbm_slope(kLargeOctaves) / kLargeSpacing;
    const double phase_slope =
        1.0 / kRippleWavelength + kRippleWarpCycles * kNoiseSlope / kRippleWarpSpacing;
    const double mask_slope =
        1.5 / (kRippleMaskHi - kRippleMaskLo) * kNoiseSlope / kRippleMaskSpacing;
    const double ripple_slope = kRippleHeight * (3.0 * phase_slope + 0.5 * mask_slope);
    const double micro_slope = kMicroAmplitude * fbm_slope(kMicroOctaves) / kMicroSpacing;
    const double bump_slope = 1.5 * kNoduleHeightMax * lumpy_profile_slope();
    m_large_slope = relief * large_slope;
    m_base_slope = relief * (large_slope + ripple_slope + micro_slope);
    m_max_slope = m_base_slope + relief * bump_slope;
}

double Seafloor::large_scale(double x, double y, Caches& c) const {
    return kLargeAmplitude * c.large(m_salt[kLargeLayer], x / kLargeSpacing, y / kLargeSpacing);
}

double Seafloor::ripple(double x, double y, Caches& c) const {
    // A smoothed triangle wave along the ripple direction (sharper crests than a sine and no
    // libm call), crests displaced by a warp noise, present in patches (mask).
    const double phase = (m_ripple_kx * x + m_ripple_ky * y) / kRippleWavelength +
                         kRippleWarpCycles * c.warp(m_salt[kRippleWarpLayer],
                                                    x / kRippleWarpSpacing, y / kRippleWarpSpacing);
    const double tri = std::fabs(2.0 * (phase - fast_floor(phase)) - 1.0);
    const double wave = tri * tri * (3.0 - 2.0 * tri) - 0.5;
    const double mask = smoothstep(
        kRippleMaskLo, kRippleMaskHi,
        c.mask(m_salt[kRippleMaskLayer], x / kRippleMaskSpacing, y / kRippleMaskSpacing));
    return wave * mask;
}

int Seafloor::gather(double x, double y, double radius, bool halo, Bump* out) const {
    // Every present bump whose disc (outline, or halo for the albedo) comes within `radius` of
    // (x, y). Cells are visited in a fixed order; the results do not depend on it anyway.
    const double far_max = (halo ? kHaloReach : kOutline) * kMaxRadius + radius;
    const auto x0 = std::int64_t(fast_floor((x - far_max) / kCell));
    const auto x1 = std::int64_t(fast_floor((x + far_max) / kCell));
    const auto y0 = std::int64_t(fast_floor((y - far_max) / kCell));
    const auto y1 = std::int64_t(fast_floor((y + far_max) / kCell));
    int n = 0;
    for (std::int64_t cy = y0; cy <= y1; ++cy) {
        for (std::int64_t cx = x0; cx <= x1; ++cx) {
            const std::uint64_t h = hash_cell(m_salt[kNoduleLayer], cx, cy);
            // Position, kind and size from one hash: this part runs for every cell visited.
            const double px = (double(cx) + bits_unit(h, 0, 21)) * kCell;
            const double py = (double(cy) + bits_unit(h, 21, 21)) * kCell;
            const bool rock = bits_unit(h, 42, 11) < kRockFraction;
            const double size = bits_unit(h, 53, 11);
            const double a = rock ? 0.03 + 0.045 * size : 0.015 + 0.06 * size * std::sqrt(size);
            const double outline = (halo ? kHaloReach : kOutline) * a;
            const double dx = x - px, dy = y - py;
            if (dx * dx + dy * dy >= (outline + radius) * (outline + radius)) continue;
            // Patches of dense nodules and of bare sediment: a cell has its bump where a
            // low-frequency density noise, taken at the cell's centre, exceeds its hash.
            const double patch =
                gradient_noise(m_salt[kDensityLayer], (double(cx) + 0.5) * kCell / kDensitySpacing,
                               (double(cy) + 0.5) * kCell / kDensitySpacing);
            const double density = 0.1 + 0.75 * smoothstep(-0.3, 0.3, patch);
            if (cell_unit(h, 4) >= density) continue;
            if (n == kMaxBumps) return n;  // cannot happen: radius <= kMaxGather
            Bump& b = out[n++];
            b.hash = h;
            b.px = px;
            b.py = py;
            b.a = a;
            b.b = a * (rock ? 0.6 + 0.4 * cell_unit(h, 5) : 0.55 + 0.45 * cell_unit(h, 5));
            double ca = cell_unit(h, 6) - 0.5, sa = cell_unit(h, 7) - 0.5;
            const double len = std::sqrt(ca * ca + sa * sa);
            b.ca = len > 1e-6 ? ca / len : 1.0;
            b.sa = len > 1e-6 ? sa / len : 0.0;
            b.ratio = rock ? 0.25 + 0.2 * cell_unit(h, 8)
                           : 0.35 + (kNoduleHeightMax - 0.35) * cell_unit(h, 8);
            b.outline = outline;
            b.rock = rock;
        }
    }
    return n;
}

void Seafloor::probe(double x, double y, const Bump* bumps, int n, Probe& p, Caches& c) const {
    // The tallest bump wins, so that overlapping nodules keep the slope bound of one.
    double bump = 0.0;
    double free = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
        const Bump& b = bumps[i];
        const double dx = x - b.px, dy = y - b.py;
        const double d2 = dx * dx + dy * dy;
        if (d2 >= b.outline * b.outline) {
            if (d2 < (free + b.outline) * (free + b.outline)) free = std::sqrt(d2) - b.outline;
            continue;
        }
        free = 0.0;
        const double u = (b.ca * dx + b.sa * dy) / b.a, v = (-b.sa * dx + b.ca * dy) / b.b;
        const double lump =
            fbm(b.hash, u * kLumpFrequency + 0.37, v * kLumpFrequency + 0.61, kLumpOctaves);
        const double q2 = (u * u + v * v) * (1.0 + kLump * lump);
        if (!b.rock) p.halo_q2 = std::min(p.halo_q2, q2);
        if (q2 >= 1.0) continue;
        const double s = 1.0 - q2;
        const double value = b.ratio * b.b * s * std::sqrt(s);
        if (p.kind == 0 || value > bump) {
            bump = value;
            p.kind = b.rock ? 2 : 1;
            p.bump_hash = b.hash;
            p.bump_q2 = q2;
        }
    }
    p.free = free;
    if (!p.with_height) return;
    p.ripple = ripple(x, y, c);
    const double micro =
        kMicroAmplitude * c.micro(m_salt[kMicroLayer], x / kMicroSpacing, y / kMicroSpacing);
    p.height = m_relief * (large_scale(x, y, c) + kRippleHeight * p.ripple + micro + bump);
}

double Seafloor::height(double x, double y) const {
    Bump bumps[kMaxBumps];
    const int n = gather(x, y, 0.0, false, bumps);
    Probe p;
    Caches c;
    probe(x, y, bumps, n, p, c);
    return p.height;
}

double Seafloor::intersect(const Vec3& o, const Vec3& d, double max_range) const {
    const double dlen = length(d);
    if (!(dlen > 0.0) || !(max_range > 0.0)) return -1.0;
    const double dz = d.z, dxy = std::sqrt(d.x * d.x + d.y * d.y);
    // The surface lies between two planes; the ray only needs marching between them.
    const double top = m_max_height + 1e-3, bottom = m_min_height - 1e-3;
    if (o.z < bottom) return 0.0;  // inside the ground
    double t_end = max_range / dlen;
    double t = 0.0;
    if (o.z > top) {
        if (dz >= 0.0) return -1.0;
        t = (top - o.z) / dz;
    }
    if (dz < 0.0) {
        t_end = std::min(t_end, (bottom - o.z) / dz);
    } else if (dz > 0.0) {
        t_end = std::min(t_end, (top - o.z) / dz);
    }
    if (t > t_end) return -1.0;

    // Phase 1: against the large-scale undulation plus the most the detail can add. That
    // lower bound of the ray's height above the surface shrinks at most at `coarse_rate` per
    // unit t, so a step of gap / rate cannot pass through the surface.
    Caches c;
    const double coarse_rate = m_large_slope * dxy - dz;
    double t_prev = t;
    while (true) {
        const double lower =
            o.z + t * dz -
            (m_relief * large_scale(o.x + t * d.x, o.y + t * d.y, c) + m_detail_above);
        if (lower <= 2e-3) break;
        if (coarse_rate <= 0.0) return -1.0;
        t_prev = t;
        t += lower / coarse_rate;
        if (t > t_end) return -1.0;
    }

    // Phase 2: the same with the full surface. Near bumps the full slope bound L holds; away
    // from them (Probe::free) the smaller bound without bumps, for as far as the step moves
    // horizontally. Where L |d_xy| < -d_z the gap decreases strictly along the ray, so it has
    // one root and a step of gap / (-d_z - L |d_xy|) reaches or passes it: one step brackets it.
    // Otherwise a step of gap / (L |d_xy| - d_z) cannot pass through the surface. Either way,
    // a positive gap at the step's end means no surface was skipped.
    // The bumps near the ray are gathered once for a disc around where phase 2 starts, and
    // again only if the ray leaves that disc.
    Bump bumps[kMaxBumps];
    int nb = -1;
    double gx = 0.0, gy = 0.0;
    Probe p;
    auto gap = [&](double tt) {
        const double x = o.x + tt * d.x, y = o.y + tt * d.y;
        double off = std::sqrt((x - gx) * (x - gx) + (y - gy) * (y - gy));
        if (nb < 0 || off >= kMaxGather) {
            gx = x;
            gy = y;
            off = 0.0;
            nb = gather(x, y, kMaxGather, false, bumps);
        }
        p = Probe();
        probe(x, y, bumps, nb, p, c);
        p.free = std::min(p.free, kMaxGather - off);
        return o.z + tt * dz - p.height;
    };
    // The longest step a slope bound allows from a point with gap f, and whether the gap is
    // monotone over it (then any shorter step is allowed too).
    auto bound_step = [&](double f, double slope, bool* monotone) {
        const double fall = -dz - slope * dxy;
        *monotone = fall > 0.0;
        return *monotone ? f / fall : f / (slope * dxy - dz);
    };
    const bool can_descend = m_max_slope * dxy - dz > 0.0;
    const double min_step = 5e-4 / dlen;  // half a millimetre along the ray
    double ta = t, fa = gap(t);
    double tb = t, fb = fa;
    if (fa <= 0.0) {
        // Only if a bound were violated: fall back to the last point known to be above.
        ta = t_prev;
        fa = gap(ta);
        if (fa <= 0.0) return ta;
    } else {
        double t_last = -1.0, f_last = 0.0;
        while (true) {
            if (!can_descend || ta >= t_end) return -1.0;
            bool monotone = false;
            double step = bound_step(fa, m_max_slope, &monotone);
            if (p.free > 0.0) {
                bool base_monotone = false;
                const double reach =
                    dxy > 0.0 ? p.free / dxy : std::numeric_limits<double>::infinity();
                const double s = std::min(bound_step(fa, m_base_slope, &base_monotone), reach);
                if (s > step) {
                    step = s;
                    monotone = base_monotone;
                }
            }
            if (monotone) {
                // Where the gap is monotone, aim a little past the predicted root (secant, or
                // a flat floor on the first step): the bracket is then tight and the
                // refinement below needs one or two evaluations.
                const double guess =
                    t_last >= 0.0 && f_last > fa ? fa * (ta - t_last) / (f_last - fa) : fa / -dz;
                step = std::min(step, 1.02 * guess);
            }
            t_last = ta;
            f_last = fa;
            tb = std::min(ta + std::max(step, min_step), t_end);
            fb = gap(tb);
            if (fb <= 0.0) break;
            ta = tb;
            fa = fb;
        }
    }
    if (fb == 0.0) return tb;

    // Illinois variant of regula falsi: exact in one step on a plane, superlinear on curves.
    int side = 0;
    double tr = tb;
    for (int it = 0; it < 40; ++it) {
        tr = (ta * fb - tb * fa) / (fb - fa);
        const double fr = gap(tr);
        if (std::fabs(fr) <= 2e-7 || tb - ta <= 1e-9 * tb) break;
        if (fr > 0.0) {
            ta = tr;
            fa = fr;
            if (side == 1) fb *= 0.5;
            side = 1;
        } else {
            tb = tr;
            fb = fr;
            if (side == -1) fa *= 0.5;
            side = -1;
        }
    }
    return tr;
}

}  // namespace deepsea
