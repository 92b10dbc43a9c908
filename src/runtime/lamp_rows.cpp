// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt); depth arrives
// sanitised (open water z == 0, never NaN or inf), as the compositor guarantees.

#include "lamp_rows.h"

#include <algorithm>
#include <cmath>

#include "clones.h"
#include "deepsea/optics/lamp.h"

namespace deepsea {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// alpha = d ln K / d cos(theta) = theta / (sigma^2 sin(theta)) (its limit 1 / sigma^2 on the
/// axis), from theta and sin(theta).
template <class T>
[[gnu::always_inline]] inline T lamp_alpha(T theta, T sin_theta, T inv_s2) {
    return sin_theta > T(1e-3) ? theta / sin_theta * inv_s2 : inv_s2;
}

}  // namespace

LampRowBound lamp_row_bound(const Light& L, const Rgb& c) {
    LampRowBound b;
    const double sigma = L.rid.sigma_deg * kDegToRad, inv_s2 = 1.0 / (sigma * sigma);
    const double limit = std::min(120.0, L.rid.cutoff_deg) * kDegToRad;
    if (!(sigma > 0.0) || !(limit > 0.0)) return b;  // never
    // alpha and its first two derivatives in cos(theta) grow with theta: the largest on a fine
    // grid of cos(theta) over [cos(limit), 1], with margins for what lies between grid points
    const auto alpha = [&](double ct) {
        const double th = std::acos(std::clamp(ct, -1.0, 1.0));
        return lamp_alpha(th, std::sin(th), inv_s2);
    };
    const double lo = std::cos(limit), h = 1e-4;
    double a1 = 0.0, a2 = 0.0, a3 = 0.0;
    const int n = 20000;
    for (int i = 0; i <= n; ++i) {
        const double ct = lo + (1.0 - lo) * i / n;
        const double x = std::clamp(ct, lo + h, 1.0 - h);
        a1 = std::max(a1, alpha(ct));
        a2 = std::max(a2, std::fabs(alpha(x + h) - alpha(x - h)) / (2.0 * h));
        a3 = std::max(a3, std::fabs(alpha(x + h) - 2.0 * alpha(x) + alpha(x - h)) / (h * h));
    }
    b.a1 = float(a1 * 1.05);
    b.a2 = float(a2 * 1.05);
    b.a3 = float(a3 * 1.2);
    b.ct_min = float(lo);
    b.c = float(std::max({c.r, c.g, c.b}));
    return b;
}

DEEPSEA_CLONES
void lamp_key_row(const Light& L, const Rgb& c, const RowGeometry& g, float* __restrict keys) {
    const int n = g.n;
    const float lx = float(L.position.x), ly = float(L.position.y), lz = float(L.position.z);
    const float ax = float(L.direction.x), ay = float(L.direction.y), az = float(L.direction.z);
    const float sig = float(L.rid.sigma_deg * kDegToRad), inv_s2 = 1.0f / (sig * sig);
    const float cutoff = float(L.rid.cutoff_deg * kDegToRad);
    const float cr = float(c.r), cg = float(c.g), cb = float(c.b);
    const float ir = float(L.intensity.r), ig = float(L.intensity.g), ib = float(L.intensity.b);
    const float* __restrict px = g.x;
    const float* __restrict py = g.y;
    const float* __restrict pz = g.z;
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float wx = lx - px[u], wy = ly - py[u], wz = lz - pz[u];
        const float d1 = std::sqrt(wx * wx + wy * wy + wz * wz);
        const float ct = -(ax * wx + ay * wy + az * wz) / d1;
        const float theta = lamp_angle<FastMath>(ct);
        // (& not &&: a branch in the loop would keep it from vectorising)
        const bool lit = (pz[u] > 0.0f) & (theta <= cutoff);
        // the lamp's Gaussian term with a spread of 1 (the spread is each pixel's own)
        keys[u] = lit ? gaussian_lamp_term<FastMath>(ir, theta, sig, 1.0f, cr, d1) : 0.0f;
        keys[n + u] = lit ? gaussian_lamp_term<FastMath>(ig, theta, sig, 1.0f, cg, d1) : 0.0f;
        keys[2 * n + u] = lit ? gaussian_lamp_term<FastMath>(ib, theta, sig, 1.0f, cb, d1) : 0.0f;
        // (no std::min / max in these loops: their references keep values in memory, and the
        // loops from vectorising)
        const float ctc = ct > 1.0f ? 1.0f : (ct < -1.0f ? -1.0f : ct);
        keys[3 * n + u] = pz[u] > 0.0f ? ct : -2.0f;
        keys[4 * n + u] = d1;
        keys[5 * n + u] = lamp_alpha(theta, std::sqrt(1.0f - ctc * ctc), inv_s2);
    }
}

namespace {

/// lamp_between_row's loop; First: writes e (so that the row needs no zeroing pass).
template <bool First>
[[gnu::always_inline]] inline void between_row(const Light& L, const Rgb& c, const LampRowBound& b,
                                               float tol, const RowGeometry& g, float t,
                                               const float* __restrict k0,
                                               const float* __restrict k1, float* __restrict e,
                                               int* __restrict fail) {
    const int n = g.n;
    const float lx = float(L.position.x), ly = float(L.position.y), lz = float(L.position.z);
    const Vec3T<float> axis{float(L.direction.x), float(L.direction.y), float(L.direction.z)};
    const float cc[3] = {float(c.r), float(c.g), float(c.b)};
    const float a1 = b.a1, a2 = b.a2, a3 = b.a3, ct_min = b.ct_min, cm = b.c;
    const float E = std::exp(kLampRowHMax);
    const float* __restrict px = g.x;
    const float* __restrict py = g.y;
    const float* __restrict pz = g.z;
    const float* __restrict nx = g.nx;
    const float* __restrict ny = g.ny;
    const float* __restrict nz = g.nz;
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const LampGeometry<float> lg =
            lamp_geometry({lx - px[u], ly - py[u], lz - pz[u]}, {nx[u], ny[u], nz[u]}, axis);
        const float spread = pz[u] > 0.0f ? lamp_spread(lg.d1, lg.cos_n) : 0.0f;
        const float ct0 = k0[3 * n + u], ct1 = k1[3 * n + u];
        const float d0 = k0[4 * n + u], d1 = k1[4 * n + u];
        const float ct_h = ct0 + t * (ct1 - ct0), d_h = d0 + t * (d1 - d0);
        const float al = k0[5 * n + u] + t * (k1[5 * n + u] - k0[5 * n + u]);
        const float dct = lg.cos_theta - ct_h, dd = lg.d1 - d_h;
#pragma GCC unroll 3
        for (int ch = 0; ch < 3; ++ch) {
            const float K0 = k0[ch * n + u], K = K0 + t * (k1[ch * n + u] - K0);
            const float x = al * dct - cc[ch] * dd;
            const float term = spread * (K * (1.0f + x));
            e[ch * n + u] = First ? term : e[ch * n + u] + term;
        }
        // the bound (lamp_rows.h)
        const float a = std::fabs(ct1 - ct0), bb = std::fabs(d1 - d0);
        const float p = std::fabs(dct), q = std::fabs(dd);
        const float H = a1 * (a + p) + cm * (bb + q), X = a1 * p + cm * q;
        const float r = 0.5f * a2 * p * p + 0.125f * a3 * a * a * p;
        const float s = a1 * a + cm * bb;
        const float bound =
            E * (0.5f * X * X * E + E * r) + (1.0f + X) * E * 0.125f * (s * s + a2 * a * a);
        const bool ok = (H <= kLampRowHMax) & (X + r <= kLampRowHMax) & (bound <= tol) &
                        (ct0 >= ct_min) & (ct1 >= ct_min) & (lg.cos_theta >= ct_min);
        fail[u] = (pz[u] > 0.0f) & !ok ? 1 : fail[u];
    }
}

}  // namespace

DEEPSEA_CLONES
void lamp_between_row(const Light& L, const Rgb& c, const LampRowBound& b, float tol,
                      const RowGeometry& g, float t, const float* k0, const float* k1, float* e,
                      bool first, int* fail) {
    if (first) {
        between_row<true>(L, c, b, tol, g, t, k0, k1, e, fail);
    } else {
        between_row<false>(L, c, b, tol, g, t, k0, k1, e, fail);
    }
}

}  // namespace deepsea
