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

/// One ray's adaptive integration: the integrand, the panels it may still spend and the stop
/// it polls.
struct Adaptive {
    const Rig& rig;
    const Water& water;
    const Vec3& dir;
    const StopFlag* stop;
    long panels_left = kMaxQuadraturePanels;

    Rgb f(double t) const { return in_scatter(rig, water, dir, t); }

    /// One GK15 panel on [a, b]: its value and error estimate, counted and polled.
    void panel(double a, double b, Rgb& k, Rgb& e) {
        throw_if_stopped(stop);
        --panels_left;
        detail::gk15<Rgb>([this](double t) { return f(t); }, a, b, k, e, abs_diff);
    }

    /// Recursive bisection until every channel's error estimate is within its share of tol, the
    /// depth is spent or the ray's panels are.
    void adapt(double a, double b, const Rgb& tol, int depth, Integral& out) {
        Rgb k, e;
        panel(a, b, k, e);
        const bool ok = e.r <= tol.r && e.g <= tol.g && e.b <= tol.b;
        // Both halves cost a panel: split only if both can be paid.
        if (ok || depth <= 0 || panels_left < 2) {
            out.value += k;
            out.error += e;
            return;
        }
        const double m = 0.5 * (a + b);
        adapt(a, m, tol * 0.5, depth - 1, out);
        adapt(m, b, tol * 0.5, depth - 1, out);
    }
};

/// Absolute tolerance per channel from a rough estimate of the integral over [t0, t1].
Rgb tolerance_for(Adaptive& ray, double t0, double t1, const Quadrature& q) {
    Rgb est, e;
    const int panels = 4;
    for (int i = 0; i < panels; ++i) {
        const double a = t0 + (t1 - t0) * i / panels, b = t0 + (t1 - t0) * (i + 1) / panels;
        Rgb k;
        ray.panel(a, b, k, e);
        est += k;
    }
    Rgb tol;
    for (int c = 0; c < 3; ++c) tol[c] = std::max(q.rel_tol * std::fabs(est[c]), q.abs_tol);
    return tol;
}

}  // namespace

Integral backscatter_integral(const Rig& rig, const Water& water, const Vec3& dir, double t0,
                              double t1, const Quadrature& q, const StopFlag* stop) {
    Integral out;
    if (!(t1 > t0)) return out;
    Adaptive ray{rig, water, dir, stop};
    const Rgb tol = tolerance_for(ray, t0, t1, q);
    ray.adapt(t0, t1, tol, q.max_depth, out);
    return out;
}

std::vector<Rgb> backscatter_cumulative(const Rig& rig, const Water& water, const Vec3& dir,
                                        const std::vector<double>& t, const Quadrature& q,
                                        const StopFlag* stop) {
    std::vector<Rgb> out(t.size());
    if (t.empty()) return out;
    Adaptive ray{rig, water, dir, stop};
    // One tolerance for the whole ray, shared among segments by length: the error of the
    // cumulative value at any sample stays within rel_tol of the ray's total.
    const double t_end = t.back();
    const Rgb total_tol = t_end > 0.0 ? tolerance_for(ray, 0.0, t_end, q) : Rgb(q.abs_tol);
    Rgb acc;
    double prev = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        if (t[k] > prev) {
            Integral seg;
            const Rgb tol = total_tol * ((t[k] - prev) / t_end);
            ray.adapt(prev, t[k], tol, q.max_depth, seg);
            acc += seg.value;
            prev = t[k];
        }
        out[k] = acc;
    }
    return out;
}

}  // namespace deepsea
