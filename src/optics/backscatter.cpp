#include "deepsea/optics/backscatter.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

/// 50 x double's epsilon: a panel's error estimate below this share of its value is rounding.
constexpr double kRoundoff = 50.0 * std::numeric_limits<double>::epsilon();

/// One ray's adaptive integration: the integrand, the panels it may still spend and the stop
/// it polls.
struct Adaptive {
    const Rig& rig;
    const Water& water;
    const Vec3& dir;
    const StopFlag* stop;
    long panels_left = kMaxQuadraturePanels;
    bool exhausted = false;        ///< a panel short of its tolerance was left unsplit
    const Vec3* origin = nullptr;  ///< the ray's start (a port's outer surface); null: the camera

    Rgb f(double t) const {
        if (!origin) return in_scatter(rig, water, dir, t);
        Rgb sum;
        const Vec3 X = *origin + dir * t;
        for (const Light& L : rig.lights) sum += lamp_in_scatter(L, water, X, -dir);
        return sum * exp(water.c * -t);
    }

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
        // A channel is done when its error is within its share of tol, or down at the
        // rounding error of its value (QUADPACK's test): no bisection improves on that, and a
        // tolerance below it (a strict rel_tol, or a first estimate that missed a lamp's peak)
        // used to bisect to max_depth around the peak.
        const auto done = [&](int c) {
            return e[c] <= tol[c] || e[c] <= kRoundoff * std::fabs(k[c]);
        };
        const bool ok = done(0) && done(1) && done(2);
        // Both halves cost a panel: split only if both can be paid.
        if (!ok && depth > 0 && panels_left < 2) exhausted = true;
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

/// A panel of the greedy pass.
struct Panel {
    double a, b;
    Rgb k, e, tol;
    int depth;
    std::size_t segment;
    double excess;  ///< the largest error / tolerance over the channels not yet done
};

/// Integrals of the segments [edges[s], edges[s + 1]] (tolerance tols[s]) within the panel
/// budget, always bisecting the panel whose error exceeds its tolerance the most (QUADPACK's
/// global strategy), for rays on which the depth-first bisection ran out of panels: it spent
/// them from the start of the ray on, and left whatever came after (a lamp's peak) coarse, 13 %
/// off on a strict ray. Deterministic: ties go to the nearer panel, sums run in ray order.
std::vector<Integral> greedy(Adaptive& ray, const std::vector<double>& edges,
                             const std::vector<Rgb>& tols, int max_depth) {
    const auto make = [&](double a, double b, const Rgb& tol, int depth, std::size_t seg) {
        Panel p{a, b, {}, {}, tol, depth, seg, 0.0};
        ray.panel(a, b, p.k, p.e);
        for (int c = 0; c < 3; ++c) {
            if (p.e[c] <= tol[c] || p.e[c] <= kRoundoff * std::fabs(p.k[c])) continue;
            p.excess = std::max(p.excess, tol[c] > 0.0 ? p.e[c] / tol[c] : HUGE_VAL);
        }
        return p;
    };
    const auto later = [](const Panel& x, const Panel& y) {
        return x.excess != y.excess ? x.excess < y.excess : x.a > y.a;
    };
    std::vector<Panel> open, closed;  // open: a heap by excess
    const auto add = [&](Panel p) {
        if (p.excess > 0.0 && p.depth > 0) {
            open.push_back(p);
            std::push_heap(open.begin(), open.end(), later);
        } else {
            closed.push_back(p);
        }
    };
    for (std::size_t s = 0; s + 1 < edges.size(); ++s) {
        if (edges[s + 1] > edges[s]) add(make(edges[s], edges[s + 1], tols[s], max_depth, s));
    }
    while (!open.empty() && ray.panels_left >= 2) {
        std::pop_heap(open.begin(), open.end(), later);
        const Panel p = open.back();
        open.pop_back();
        const double m = 0.5 * (p.a + p.b);
        add(make(p.a, m, p.tol * 0.5, p.depth - 1, p.segment));
        add(make(m, p.b, p.tol * 0.5, p.depth - 1, p.segment));
    }
    closed.insert(closed.end(), open.begin(), open.end());
    std::sort(closed.begin(), closed.end(), [](const Panel& x, const Panel& y) {
        return x.segment != y.segment ? x.segment < y.segment : x.a < y.a;
    });
    std::vector<Integral> out(edges.size() > 0 ? edges.size() - 1 : 0);
    for (const Panel& p : closed) {
        out[p.segment].value += p.k;
        out[p.segment].error += p.e;
    }
    return out;
}

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
    return backscatter_integral(rig, water, Vec3(0.0, 0.0, 0.0), dir, t0, t1, q, stop);
}

Integral backscatter_integral(const Rig& rig, const Water& water, const Vec3& origin,
                              const Vec3& dir, double t0, double t1, const Quadrature& q,
                              const StopFlag* stop) {
    Integral out;
    if (!(t1 > t0)) return out;
    Adaptive ray{rig, water, dir, stop};
    if (origin.x != 0.0 || origin.y != 0.0 || origin.z != 0.0) ray.origin = &origin;
    const Rgb tol = tolerance_for(ray, t0, t1, q);
    ray.adapt(t0, t1, tol, q.max_depth, out);
    if (ray.exhausted) {
        ray.panels_left = kMaxQuadraturePanels;
        return greedy(ray, {t0, t1}, {tol}, q.max_depth)[0];
    }
    return out;
}

std::vector<Rgb> backscatter_cumulative(const Rig& rig, const Water& water, const Vec3& dir,
                                        const std::vector<double>& t, const Quadrature& q,
                                        const StopFlag* stop) {
    return backscatter_cumulative(rig, water, Vec3(0.0, 0.0, 0.0), dir, t, q, stop);
}

std::vector<Rgb> backscatter_cumulative(const Rig& rig, const Water& water, const Vec3& origin,
                                        const Vec3& dir, const std::vector<double>& t,
                                        const Quadrature& q, const StopFlag* stop) {
    std::vector<Rgb> out(t.size());
    if (t.empty()) return out;
    Adaptive ray{rig, water, dir, stop};
    if (origin.x != 0.0 || origin.y != 0.0 || origin.z != 0.0) ray.origin = &origin;
    // One tolerance for the whole ray, shared among segments by length: the error of the
    // cumulative value at any sample stays within rel_tol of the ray's total.
    const double t_end = t.back();
    const Rgb total_tol = t_end > 0.0 ? tolerance_for(ray, 0.0, t_end, q) : Rgb(q.abs_tol);
    // Segments between the distinct samples: edges[s] .. edges[s + 1] ends at sample ends[s].
    std::vector<double> edges{0.0};
    std::vector<std::size_t> ends;
    std::vector<Rgb> tols;
    for (std::size_t k = 0; k < t.size(); ++k) {
        if (t[k] > edges.back()) {
            tols.push_back(total_tol * ((t[k] - edges.back()) / t_end));
            edges.push_back(t[k]);
            ends.push_back(k);
        }
    }
    std::vector<Integral> seg(ends.size());
    for (std::size_t s = 0; s < ends.size(); ++s)
        ray.adapt(edges[s], edges[s + 1], tols[s], q.max_depth, seg[s]);
    if (ray.exhausted) {
        ray.panels_left = kMaxQuadraturePanels;
        seg = greedy(ray, edges, tols, q.max_depth);
    }
    Rgb acc;
    for (std::size_t k = 0, s = 0; k < t.size(); ++k) {
        if (s < ends.size() && ends[s] == k) acc += seg[s++].value;
        out[k] = acc;
    }
    return out;
}

}  // namespace deepsea
