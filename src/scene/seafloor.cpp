// Procedural seafloor: height field, albedo texture and ray marching (flight.cpp renders
// frames with it). docs/scene.md describes the model; the numbers below are its parameters.

#include "deepsea/scene/seafloor.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "noise.h"

namespace deepsea {

using namespace scene_detail;

namespace {

// Salt slots: every layer of the seafloor draws from its own hash stream.
enum Layer : int {
    kLargeLayer,
    kRippleWarpLayer,
    kRippleMaskLayer,
    kMicroLayer,
    kNoduleLayer,
    kDensityLayer,
    kSandLayer,
    kGrainLayer,
    kSpeckLayer,
    kShellLayer,
    kRippleDirLayer,
    kLayerCount,
};

// Large-scale undulation: fBm, lattice spacing of the first octave in metres.
constexpr double kLargeSpacing = 7.0;
constexpr double kLargeAmplitude = 0.2;  // m; typical +-0.1 m, bound +-0.26 m
constexpr int kLargeOctaves = 3;

// Sand ripples: crest-to-trough height and wavelength (m), crests meandered by a warp noise
// and present only in patches (mask noise), as on current-swept sediment.
constexpr double kRippleWavelength = 0.13;
constexpr double kRippleHeight = 0.012;
constexpr double kRippleWarpSpacing = 1.2;  // m
constexpr double kRippleWarpCycles = 1.0;   // crest displacement, in wavelengths
constexpr double kRippleMaskSpacing = 2.5;  // m
constexpr double kRippleMaskLo = -0.1, kRippleMaskHi = 0.25;

// Micro-relief: mm-scale roughness that gives the depth map's normals some texture.
constexpr double kMicroSpacing = 0.04;
constexpr double kMicroAmplitude = 0.0015;
constexpr int kMicroOctaves = 2;

// Nodules and rocks: at most one per square cell of kCell metres, centre anywhere in the cell,
// semi-major axis at most kMaxRadius; with the lumpy outline, at most kOutline * kMaxRadius
// from its centre.
constexpr double kCell = 0.15;
constexpr double kMaxRadius = 0.075;
constexpr double kDensitySpacing = 3.0;  // m, size of dense and sparse nodule patches
constexpr double kRockFraction = 0.04;   // of bumps that are rocks instead of nodules
constexpr double kLump = 0.35;           // relative distortion of the outline (lumpiness)
constexpr double kLumpFrequency = 1.1;   // lattice cells of lump noise per semi-axis
constexpr int kLumpOctaves = 2;
constexpr double kNoduleHeightMax = 0.6;  // height / semi-minor axis, nodules
constexpr double kHaloReach = 1.5;        // stained sediment out to this many radii
// q^2 = r^2 (1 + kLump lump) lies within r^2 [kLumpLo, kLumpHi].
const double kLumpLo = 1.0 - kLump * kNoiseMax * fbm_amplitude(kLumpOctaves);
const double kLumpHi = 1.0 + kLump * kNoiseMax * fbm_amplitude(kLumpOctaves);
// A bump of semi-major axis a covers at most the disc of radius a * kOutline.
const double kOutline = 1.0 / std::sqrt(kLumpLo);

// gather() collects the bumps within at most kMaxGather metres of a point; a 4 x 4 block of
// cells covers that disc plus the largest halo, so kMaxBumps is never reached.
constexpr double kMaxGather = 0.05;
constexpr int kMaxBumps = 16;

// Albedo-only layers: bright specks (forams, shell grit) and shell fragments.
constexpr double kSpeckCell = 0.03;
constexpr double kShellCell = 0.5;

Rgb mix(const Rgb& a, const Rgb& b, double t) { return a + (b - a) * t; }

Rgb clamp01(const Rgb& c) {
    return {scene_detail::clamp01(c.r), scene_detail::clamp01(c.g), scene_detail::clamp01(c.b)};
}

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

/// What probe() finds at a point besides the height: what the albedo needs, and how far the
/// nearest bump is (for the ray marcher).
struct Seafloor::Probe {
    bool with_height = true;  // false: albedo only (no height terms, bumps out to the halo)
    double height = 0.0;
    double ripple = 0.0;          // ripple(x, y); albedo mode: the caller sets it
    int kind = 0;                 // 0 sand, 1 nodule, 2 rock: the bump that covers the point
    std::uint64_t bump_hash = 0;  // cell hash of that bump
    double bump_q2 = 1.0;         // its normalised radius^2 (0 centre, 1 rim)
    double halo_q2 = 1e9;         // smallest normalised radius^2 of a nodule nearby
    double free = 0.0;            // no bump outline within this distance (m) among those given
};

/// Noise lattice caches for a run of nearby evaluations (one ray, one pixel): the same values
/// as uncached, cheaper.
struct Seafloor::Caches {
    FbmCache<kLargeOctaves> large;
    NoiseCache warp, mask;
    FbmCache<kMicroOctaves> micro;
};

/// One nodule or rock, as gather() finds it.
struct Seafloor::Bump {
    std::uint64_t hash;  // cell hash: the bump's own random stream
    double px, py;       // centre, m
    double a, b;         // semi-axes, m (a >= b)
    double ca, sa;       // direction of the a axis
    double ratio;        // height / b
    double outline;      // radius of the disc that holds the outline (or the halo), m
    bool rock;
};

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

Rgb Seafloor::sediment_base(double x, double y) const {
    // Grey-brown and beige patches, a broad brightness variation, a slight hue drift and
    // darker organic blotches, mottling: all several pixels wide at the default view, so once
    // per pixel is enough.
    const std::uint64_t sand = m_salt[kSandLayer];
    const double patch = smoothstep(-0.45, 0.45, fbm(sand, x / 1.3, y / 1.3, 3));
    Rgb c = mix(Rgb(0.30, 0.26, 0.205), Rgb(0.40, 0.315, 0.20), patch);
    c = c * (1.0 + 0.12 * gradient_noise(sand + 7, x / 5.0, y / 5.0));
    const double hue = 0.05 * gradient_noise(sand + 11, x / 0.4, y / 0.4);
    c = Rgb(c.r * (1.0 + hue), c.g, c.b * (1.0 - hue));
    const double blotch = smoothstep(0.2, 0.5, gradient_noise(sand + 13, x / 0.12, y / 0.12));
    // Mottling at a few centimetres: still several pixels wide at the default view.
    const double mottle = 0.08 * gradient_noise(sand + 17, x / 0.05, y / 0.05) +
                          0.06 * gradient_noise(sand + 19, x / 0.02, y / 0.02);
    return c * (1.0 - 0.12 * blotch + mottle);
}

Rgb Seafloor::shade(double x, double y, const Probe& p, const Rgb& base,
                    SeafloorMaterial* material) const {
    const std::uint64_t grain = m_salt[kGrainLayer];
    if (p.kind == 1) {
        // Manganese nodule: dark brown-black, each a little different, mottled, with a thin
        // dusting of sediment toward the top.
        const std::uint64_t h = p.bump_hash;
        const double tone = 0.75 + 0.5 * cell_unit(h, 9);
        Rgb c = Rgb(0.085, 0.066, 0.058) * tone;
        c = c * (1.0 + 0.3 * gradient_noise(h ^ grain, x / 0.012, y / 0.012) +
                 0.2 * gradient_noise(h ^ grain, x / 0.005, y / 0.005));
        const double dust = 0.5 * cell_unit(h, 10) * (1.0 - p.bump_q2) *
                            smoothstep(0.0, 0.4, gradient_noise(h, x / 0.01, y / 0.01));
        c = mix(c, base, dust);
        *material = SeafloorMaterial::Nodule;
        return clamp01(c);
    }
    if (p.kind == 2) {
        // Rock: brownish grey, mottled with lighter and darker grains.
        const std::uint64_t h = p.bump_hash;
        const double tone = 0.8 + 0.5 * cell_unit(h, 9);
        Rgb c = Rgb(0.15, 0.13, 0.11) * tone;
        c = c * (1.0 + 0.45 * fbm(h, x / 0.01, y / 0.01, 2));
        *material = SeafloorMaterial::Rock;
        return clamp01(c);
    }

    // Shell fragments: rare, pale, elliptical, flat (albedo only); kept inside their cell so
    // that one cell lookup is enough.
    {
        const double gx = x / kShellCell, gy = y / kShellCell;
        const auto ix = std::int64_t(fast_floor(gx)), iy = std::int64_t(fast_floor(gy));
        const std::uint64_t h = hash_cell(m_salt[kShellLayer], ix, iy);
        if (bits_unit(h, 0, 16) < 0.3) {
            const double a = 0.006 + 0.012 * bits_unit(h, 16, 16);
            const double px = (double(ix) + bits_unit(h, 32, 16)) * kShellCell;
            const double py = (double(iy) + bits_unit(h, 48, 16)) * kShellCell;
            const double cx =
                std::clamp(px, double(ix) * kShellCell + a, (double(ix) + 1.0) * kShellCell - a);
            const double cy =
                std::clamp(py, double(iy) * kShellCell + a, (double(iy) + 1.0) * kShellCell - a);
            const double dx = (x - cx) / a;
            const double dy = (y - cy) / (a * (0.45 + 0.5 * cell_unit(h, 4)));
            if (dx * dx + dy * dy < 1.0) {
                const double t = 0.85 + 0.15 * gradient_noise(h, x / 0.004, y / 0.004);
                *material = SeafloorMaterial::Shell;
                return clamp01(Rgb(0.68, 0.64, 0.56) * t);
            }
        }
    }
    // Specks, 1-4 mm: mostly bright (foraminifera, shell grit), some dark; inside their cell.
    {
        const double gx = x / kSpeckCell, gy = y / kSpeckCell;
        const double fx = fast_floor(gx), fy = fast_floor(gy);
        const std::uint64_t h = hash_cell(m_salt[kSpeckLayer], std::int64_t(fx), std::int64_t(fy));
        const double kind = bits_unit(h, 0, 16);
        if (kind < 0.3) {
            const double size = bits_unit(h, 16, 16);
            const double r = (0.001 + 0.003 * size * size) / kSpeckCell;
            const double px = r + (1.0 - 2.0 * r) * bits_unit(h, 32, 16);
            const double py = r + (1.0 - 2.0 * r) * bits_unit(h, 48, 16);
            const double dx = gx - fx - px, dy = gy - fy - py;
            if (dx * dx + dy * dy < r * r) {
                if (kind < 0.22) {
                    *material = SeafloorMaterial::Shell;
                    return clamp01(Rgb(0.62, 0.6, 0.5) * (0.8 + 0.3 * cell_unit(h, 4)));
                }
                *material = SeafloorMaterial::Sand;
                return base * 0.35;
            }
        }
    }

    // Sediment: the base colour with fine grain, slightly lighter ripple crests, and a
    // stained halo around nodules.
    const double fine = 0.16 * gradient_noise(grain, x / 0.008, y / 0.008) +
                        0.10 * gradient_noise(grain + 1, x / 0.004, y / 0.004);
    Rgb c = base * (1.0 + fine + 0.05 * p.ripple);
    if (p.halo_q2 < kHaloReach * kHaloReach) {
        c = c * (1.0 - 0.2 * smoothstep(kHaloReach * kHaloReach, 1.0, p.halo_q2));
    }
    *material = SeafloorMaterial::Sand;
    return clamp01(c);
}

SeafloorSample Seafloor::sample(double x, double y) const {
    SeafloorSample s;
    s.height = height(x, y);
    Bump bumps[kMaxBumps];
    const int n = gather(x, y, 0.0, true, bumps);
    Probe p;
    p.with_height = false;
    Caches c;
    probe(x, y, bumps, n, p, c);
    p.ripple = ripple(x, y, c);
    s.albedo = shade(x, y, p, sediment_base(x, y), &s.material);
    return s;
}

Rgb Seafloor::albedo(double x, double y) const { return mean_albedo(&x, &y, 1); }

Rgb Seafloor::mean_albedo(const double* x, const double* y, int n) const {
    if (n <= 0) return {};
    double mx = 0.0, my = 0.0;
    for (int i = 0; i < n; ++i) {
        mx += x[i];
        my += y[i];
    }
    mx /= n;
    my /= n;
    double spread = 0.0;
    for (int i = 0; i < n; ++i) {
        const double ex = x[i] - mx, ey = y[i] - my;
        spread = std::max(spread, std::sqrt(ex * ex + ey * ey));
    }
    const Rgb base = sediment_base(mx, my);
    Caches c;
    const double crest = ripple(mx, my, c);
    // One gather for the whole footprint unless it is too wide (far, grazing pixels).
    Bump bumps[kMaxBumps];
    const bool shared = spread <= kMaxGather;
    int nb = shared ? gather(mx, my, spread, true, bumps) : 0;
    Rgb sum;
    SeafloorMaterial material;
    for (int i = 0; i < n; ++i) {
        if (!shared) nb = gather(x[i], y[i], 0.0, true, bumps);
        Probe p;
        p.with_height = false;
        p.ripple = crest;
        probe(x[i], y[i], bumps, nb, p, c);
        sum += shade(x[i], y[i], p, base, &material);
    }
    return sum / double(n);
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
