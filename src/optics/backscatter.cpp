#include "deepsea/optics/backscatter.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "deepsea/core/error.h"
#include "quadrature.h"

namespace deepsea {

void validate(const Quadrature& q) {
    if (!(q.rel_tol >= kMinRelTol && q.rel_tol <= kMaxRelTol)) {
        std::ostringstream os;
        os << "quadrature rel_tol must be in [" << kMinRelTol << ", " << kMaxRelTol << "], got "
           << q.rel_tol;
        throw ConfigError(os.str());
    }
    if (!(q.abs_tol >= 0.0) || q.max_depth < 1 || q.max_depth > kMaxQuadratureDepth) {
        throw ConfigError("quadrature: abs_tol must be >= 0 and max_depth in [1, " +
                          std::to_string(kMaxQuadratureDepth) + "]");
    }
}

Rgb lamp_in_scatter(const Light& L, const Water& water, const Vec3& X, const Vec3& out,
                    double* d1_out) {
    const Vec3 lx = X - L.position;
    const double d1 = length(lx);
    if (d1_out) *d1_out = d1;
    if (!(d1 > 0.0)) return {};  // the point is the lamp itself
    const Vec3 w = lx / d1;      // light -> X
    return L.intensity_toward(w) * water.beta(dot(w, out)) * exp(water.c * -d1) * (1.0 / (d1 * d1));
}

Rgb in_scatter(const Rig& rig, const Water& water, const Vec3& dir, double t) {
    const Vec3 X = dir * t;
    Rgb sum;
    // scattered toward the camera: out = -dir
    for (const Light& L : rig.lights) sum += lamp_in_scatter(L, water, X, -dir);
    return sum * exp(water.c * -t);
}

namespace {

Rgb abs_diff(const Rgb& a, const Rgb& b) {
    return {std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b)};
}

/// Recursive bisection until every channel's error estimate is within its share of tol.
void adapt(const Rig& rig, const Water& water, const Vec3& dir, double a, double b, const Rgb& tol,
           int depth, Integral& out) {
    const auto f = [&](double t) { return in_scatter(rig, water, dir, t); };
    Rgb k, e;
    detail::gk15<Rgb>(f, a, b, k, e, abs_diff);
    const bool ok = e.r <= tol.r && e.g <= tol.g && e.b <= tol.b;
    if (ok || depth <= 0) {
        out.value += k;
        out.error += e;
        return;
    }
    const double m = 0.5 * (a + b);
    adapt(rig, water, dir, a, m, tol * 0.5, depth - 1, out);
    adapt(rig, water, dir, m, b, tol * 0.5, depth - 1, out);
}

/// Absolute tolerance per channel from a rough estimate of the integral over [t0, t1].
Rgb tolerance_for(const Rig& rig, const Water& water, const Vec3& dir, double t0, double t1,
                  const Quadrature& q) {
    Rgb est, e;
    const int panels = 4;
    for (int i = 0; i < panels; ++i) {
        const double a = t0 + (t1 - t0) * i / panels, b = t0 + (t1 - t0) * (i + 1) / panels;
        Rgb k;
        detail::gk15<Rgb>([&](double t) { return in_scatter(rig, water, dir, t); }, a, b, k, e,
                          abs_diff);
        est += k;
    }
    Rgb tol;
    for (int c = 0; c < 3; ++c) tol[c] = std::max(q.rel_tol * std::fabs(est[c]), q.abs_tol);
    return tol;
}

}  // namespace

Integral backscatter_integral(const Rig& rig, const Water& water, const Vec3& dir, double t0,
                              double t1, const Quadrature& q) {
    Integral out;
    if (!(t1 > t0)) return out;
    adapt(rig, water, dir, t0, t1, tolerance_for(rig, water, dir, t0, t1, q), q.max_depth, out);
    return out;
}

std::vector<Rgb> backscatter_cumulative(const Rig& rig, const Water& water, const Vec3& dir,
                                        const std::vector<double>& t, const Quadrature& q) {
    std::vector<Rgb> out(t.size());
    if (t.empty()) return out;
    // One tolerance for the whole ray, shared among segments by length: the error of the
    // cumulative value at any sample stays within rel_tol of the ray's total.
    const double t_end = t.back();
    const Rgb total_tol =
        t_end > 0.0 ? tolerance_for(rig, water, dir, 0.0, t_end, q) : Rgb(q.abs_tol);
    Rgb acc;
    double prev = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        if (t[k] > prev) {
            Integral seg;
            const Rgb tol = total_tol * ((t[k] - prev) / t_end);
            adapt(rig, water, dir, prev, t[k], tol, q.max_depth, seg);
            acc += seg.value;
            prev = t[k];
        }
        out[k] = acc;
    }
    return out;
}

}  // namespace deepsea
