#pragma once
// Internal to the runtime: Gaussian lamps' light on rows between key rows, the compositor's
// bounded approximation for the image alone (docs/runtime-approximations.md, "Lamp rows").

#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/lamps.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

/// Floats a key row holds per lamp and pixel: K_r, K_g, K_b, cos(theta), d1, alpha.
constexpr int kLampKeyPlanes = 6;

/// One Gaussian lamp's constants for the bound. The lamp's light at a surface point is
/// spread * K, spread = max(0, n . w) / d1^2 (exact per pixel) and K = I exp(-theta^2 /
/// (2 sigma^2) - c d1), a smooth function of two numbers, cos(theta) and d1. Between key rows
/// K is interpolated from the key rows' K and corrected to first order in the pixel's own
/// cos(theta) and d1: K ~ lerp(K) (1 + lerp(alpha) (ct - lerp(ct)) - c (d1 - lerp(d1))), alpha
/// = d ln K / d cos(theta) = theta / (sigma^2 sin(theta)). With a = |ct1 - ct0|, b = |d1' -
/// d0'| (the key rows'), p = |ct - lerp(ct)|, q = |d1 - lerp(d1)|, E = e^h_max and c the
/// largest channel's, the error relative to the pixel's own K is at most
///   E (X^2 / 2 E + E r) + (1 + X) E ((a1 a + c b)^2 + a2 a^2) / 8,
/// X = a1 p + c q, r = a2 p^2 / 2 + a3 a^2 p / 8, where a1, a2, a3 bound alpha and its first
/// two derivatives in cos(theta), provided that every cos(theta) is >= ct_min and that
/// a1 (a + p) + c (b + q) and X + r are <= h_max: the second-order rest of the interpolation,
/// the linearisation and e^x ~ 1 + x.
/// (LampRowBound, lamps.h, holds a1, a2, a3, ct_min and c.)

/// e^h_max in the bound above, with h_max = 0.25.
constexpr float kLampRowHMax = 0.25f;

/// The bound's constants of a Gaussian lamp in water of attenuation c.
LampRowBound lamp_row_bound(const Light& L, const Rgb& c);

/// A key row of one lamp: n pixels' K (per channel, W/sr before the spread), cos(theta), d1 and
/// alpha into keys[q * n + u], q < kLampKeyPlanes. Open water: K 0 and cos(theta) -2 (never
/// within a bound).
void lamp_key_row(const Light& L, const Rgb& c, const RowGeometry& g, float* keys);

/// One lamp's light on a row at weight t between key rows k0 (t = 0) and k1 (t = 1), into the
/// planar RGB row e (first: written, else added), each pixel's exact spread times the corrected
/// K. Pixels whose bound exceeds tol get fail[u] = 1 (others are left as they are): the caller
/// computes them exactly.
void lamp_between_row(const Light& L, const Rgb& c, const LampRowBound& b, float tol,
                      const RowGeometry& g, float t, const float* k0, const float* k1, float* e,
                      bool first, int* fail);

}  // namespace deepsea
