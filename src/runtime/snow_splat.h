#pragma once
// Marine snow's drawn particles (marine_snow_draw.cpp): a particle's disc, streak and band
// entry as the drawing reads them, and the disc's and streak's coverage of a pixel.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "snow_place.h"

namespace deepsea::snow_splat {

/// A particle as drawn: pixel centre, disc radius (0.5: a bilinear splat into four pixels),
/// planar depth, the light it brings (radiance times its image's area in pixels, per channel)
/// and the disc's coverage normaliser.
struct Splat {
    float u, v, radius, z;
    float energy[3];
    float inv_cover;
    int ua, va, vb;    ///< first column, rows touched
    int ba, bb;        ///< bands touched (on the image)
    bool dot;          ///< a still sub-pixel particle: a bilinear splat into four pixels
    std::uint32_t id;  ///< 0: not drawn
    /// A streak (len > 0): the disc swept from (ax, ay) along the unit (dx, dy) for len
    /// pixels, reaching rh pixels from the segment; a sub-pixel particle's as n bilinear
    /// splats at the midpoints of n equal steps.
    float ax, ay, dx, dy, len, rh;
    int n;
};

/// A band's entry where only `final` is drawn: a still sub-pixel splat's fields that
/// Target::dot reads (z > 0), or (z < 0) the index of a splat drawn by Target::draw in `ua`.
/// Written in band order by the counting sort, so that a band reads its particles in sequence
/// (32 bytes each) rather than each one's record in id order across the frame.
struct DotEntry {
    float u, v, z;
    float energy[3];
    int ua, va;
};

inline bool open_water(float z) { return !(z > 0.0f) || !std::isfinite(z); }

/// Coverage of pixel (x, y) by a disc of radius R centred at (u, v): linear over the last
/// pixel.
inline float coverage(float u, float v, float R, int x, int y) {
    const float dx = float(x) - u, dy = float(y) - v;
    return std::clamp(R + 0.5f - std::sqrt(dx * dx + dy * dy), 0.0f, 1.0f);
}

/// Where a disc is drawn: every pixel it touches, also off the image (so that an edge
/// particle loses what falls outside).
struct Window {
    int ua, ub, va, vb;
};

inline Window window(const Splat& s) {
    if (s.len > 0.0f) {
        const float bx = s.ax + s.len * s.dx, by = s.ay + s.len * s.dy;
        return {ifloor(std::min(s.ax, bx) - s.rh), iceil(std::max(s.ax, bx) + s.rh),
                ifloor(std::min(s.ay, by) - s.rh), iceil(std::max(s.ay, by) + s.rh)};
    }
    if (s.radius <= 0.5f) {
        const int x0 = ifloor(s.u), y0 = ifloor(s.v);
        return {x0, x0 + 1, y0, y0 + 1};
    }
    const float R = s.radius;
    return {ifloor(s.u - R - 0.5f), iceil(s.u + R + 0.5f), ifloor(s.v - R - 0.5f),
            iceil(s.v + R + 0.5f)};
}

/// Integral over s in [0, x] (x >= 0) of the still disc's coverage (coverage(): radius R, linear
/// over the last pixel) along a line at distance h from its centre; ri2 = (R - 1/2)^2 - h^2,
/// ro = R + 1/2, so = sqrt(ro^2 - h^2) > 0.
inline float cover_integral(float x, float h2, float ri2, float ro, float so) {
    const float si = ri2 > 0.0f ? std::sqrt(ri2) : 0.0f;
    x = std::min(x, so);
    if (x <= si) return x;
    // Beyond si the coverage is ro - sqrt(h^2 + s^2): its integral from si to x.
    const float r = std::sqrt(h2 + x * x), r_in = std::sqrt(h2 + si * si);
    const float log_term = h2 > 1e-12f ? h2 * std::log((x + r) / (si + r_in)) : 0.0f;
    return si + ro * (x - si) - 0.5f * (x * r - si * r_in + log_term);
}

/// Weight of pixel (x, y) under a streak of a disc wider than a pixel: the still disc's coverage
/// of the pixel's centre integrated along the segment, that is the exposure time it covers it
/// (in pixels of travel).
inline float sweep(const Splat& s, int x, int y) {
    const float px = float(x) - s.ax, py = float(y) - s.ay;
    const float along = px * s.dx + py * s.dy, across = px * s.dy - py * s.dx;
    const float h2 = across * across, ro = s.radius + 0.5f, so2 = ro * ro - h2;
    if (!(so2 > 0.0f)) return 0.0f;
    const float ri = s.radius - 0.5f, ri2 = ri * ri - h2, so = std::sqrt(so2);
    // The coverage is even in s: the integral over [along - len, along] of it.
    const auto G = [&](float t) {
        const float g = cover_integral(std::fabs(t), h2, ri2, ro, so);
        return t < 0.0f ? -g : g;
    };
    return std::max(0.0f, G(along) - G(along - s.len));
}

/// The part of a streak's segment within rh of row y: parameters [t0, t1] along it and the
/// columns [ca, cb] it may touch (widened by rh); none when t0 > t1.
struct RowSpan {
    float t0, t1;
    int ca, cb;
};

inline RowSpan row_span(const Splat& s, int y) {
    float t0 = 0.0f, t1 = s.len;
    const float ry = float(y) - s.ay;
    if (std::fabs(s.dy) > 1e-6f) {
        float ta = (ry - s.rh) / s.dy, tb = (ry + s.rh) / s.dy;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return {1.0f, 0.0f, 1, 0};
    } else if (std::fabs(ry) > s.rh) {
        return {1.0f, 0.0f, 1, 0};
    }
    const float xa = s.ax + t0 * s.dx, xb = s.ax + t1 * s.dx;
    return {t0, t1, ifloor(std::min(xa, xb) - s.rh), iceil(std::max(xa, xb) + s.rh)};
}

}  // namespace deepsea::snow_splat
