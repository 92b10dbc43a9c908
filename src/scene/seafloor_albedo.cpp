// Procedural seafloor: the albedo texture (sediment, nodules, rocks, shell fragments and
// specks). The parameters are in seafloor_parts.h.

#include <algorithm>
#include <cmath>

#include "deepsea/scene/seafloor.h"
#include "noise.h"
#include "seafloor_parts.h"

namespace deepsea {

using namespace scene_detail;

namespace {

Rgb mix(const Rgb& a, const Rgb& b, double t) { return a + (b - a) * t; }

Rgb clamp01(const Rgb& c) {
    return {scene_detail::clamp01(c.r), scene_detail::clamp01(c.g), scene_detail::clamp01(c.b)};
}

}  // namespace

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

}  // namespace deepsea
