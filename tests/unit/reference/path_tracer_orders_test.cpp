// Orders 2 and 3 of the path tracer against an independent integration: an isotropic lamp in
// water that only scatters (c = b), with an isotropic phase function. Then the light that has
// scattered n times has a spherically symmetric fluence phi_n(rho) about the lamp, and
//   phi_0(rho) = I exp(-c rho) / rho^2,
//   phi_n(rho) = b / (2 rho) int_0^inf phi_(n-1)(r) r [E1(c |rho - r|) - E1(c (rho + r))] dr
// (the point kernel exp(-c R) / (4 pi R^2) averaged over a sphere of radius r about the lamp;
// e.g. Case & Zweifel, "Linear Transport Theory", 1967), and the radiance reaching the camera
// after n + 1 scatterings is
//   L_(n+1) = b / (4 pi) int_0^T exp(-c t) phi_n(|t d - L|) dt
// along a pixel's unit direction d, T where its open water ends. Nothing here is shared with
// the path tracer: 1-D integrals by the tanh-sinh rule, E1 from the standard library.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "deepsea/reference/path_tracer.h"
#include "reference_fixtures.h"

namespace deepsea {

namespace {

/// Integral of f(x, x - a, b - x) over [a, b] by the tanh-sinh rule (Takahasi & Mori 1974),
/// which integrates the ends' logarithmic singularities to about 1e-9 with step 1/16.
template <class F>
double tanh_sinh(F f, double a, double b) {
    const double h = 1.0 / 16.0;
    double sum = 0.0;
    for (int k = -56; k <= 56; ++k) {
        const double t = k * h, s = 0.5 * M_PI * std::sinh(t), ch = std::cosh(s);
        const double w = 0.5 * M_PI * std::cosh(t) / (ch * ch);
        const double da = (b - a) / (1.0 + std::exp(-2.0 * s)),
                     db = (b - a) / (1.0 + std::exp(2.0 * s));
        if (da > 0.0 && db > 0.0) sum += w * f(a + da, da, db);
    }
    return sum * 0.5 * (b - a) * h;
}

double e1(double x) { return -std::expint(-x); }

/// E1(c |rho - r|) - E1(c (rho + r)), without the cancellation where r << rho or rho << r.
double kernel(double c, double rho, double r, double gap) {
    const double lo = std::min(rho, r), hi = std::max(rho, r);
    if (lo < 1e-5 * hi) return 2.0 * lo * std::exp(-c * hi) / hi;
    return e1(c * gap) - e1(c * (rho + r));
}

/// phi_n on a log grid of rho, linear in log-log between nodes.
struct Fluence {
    double lo = 1e-3, hi = 300.0;
    std::vector<double> log_phi;
    double operator()(double rho) const {
        const int n = int(log_phi.size());
        const double x = std::log(rho / lo) / std::log(hi / lo) * (n - 1);
        if (x >= n - 1) return 0.0;
        if (x <= 0.0) return std::exp(log_phi[0]) * lo / rho;  // phi ~ 1 / rho at the lamp
        const int i = int(x);
        return std::exp(log_phi[i] + (x - i) * (log_phi[i + 1] - log_phi[i]));
    }
};

/// phi_n from phi_(n-1) (`prev`, null for phi_0, intensity 1), water c = b.
Fluence next_order(double c, const Fluence* prev) {
    Fluence out;
    const int n = 700;
    out.log_phi.resize(n);
    const auto source = [&](double r) {  // phi_(n-1)(r) r
        return prev ? (*prev)(r)*r : std::exp(-c * r) / r;
    };
    for (int i = 0; i < n; ++i) {
        const double rho = out.lo * std::pow(out.hi / out.lo, double(i) / (n - 1));
        const double inner = tanh_sinh(
            [&](double r, double, double gap) { return source(r) * kernel(c, rho, r, gap); }, 0.0,
            rho);
        const double outer = tanh_sinh(
            [&](double r, double gap, double) { return source(r) * kernel(c, rho, r, gap); }, rho,
            rho + 40.0 / c);
        out.log_phi[i] = std::log(c / (2.0 * rho) * (inner + outer));
    }
    return out;
}

/// Orders `order` of the path tracer against the integrals, per 4x4 bin and over the image.
void expect_order(int order) {
    const Camera cam = testing::camera(16, 12);
    const Rgb cb(0.3, 0.5, 0.8);
    Water w = testing::hg_water(cb, cb, 0.0);
    Light lamp;
    lamp.position = {1.0, 0.3, 0.5};  // outside the field of view
    lamp.rid.kind = Rid::Kind::Table;
    lamp.rid.angle_deg = {0.0, 180.0};
    lamp.rid.value = {1.0, 1.0};
    const Rig rig{"iso", {lamp}};
    const double z_open = 8.0;
    const testing::Scene s = testing::plane(cam, 0.0);
    PathTracerOptions opt;
    opt.paths = 1024;
    opt.min_order = opt.max_order = order;
    opt.open_water_z = z_open;
    const PathTraced pt = render_path_traced(cam, rig, w, s.rgb, s.depth, opt);

    Image want(cam.width, cam.height, 3);
    for (int ch = 0; ch < 3; ++ch) {
        const double c = cb[ch];
        Fluence phi = next_order(c, nullptr);
        for (int k = 2; k < order; ++k) phi = next_order(c, &phi);
        for (int v = 0; v < cam.height; ++v) {
            for (int u = 0; u < cam.width; ++u) {
                const Vec3 r = cam.ray(u, v), d = normalize(r);
                want.at(u, v, ch) =
                    float(c / (4.0 * M_PI) *
                          tanh_sinh(
                              [&](double t, double, double) {
                                  return std::exp(-c * t) * phi(length(d * t - lamp.position));
                              },
                              0.0, z_open * length(r)));
            }
        }
    }
    double worst = 0.0;
    for (int ch = 0; ch < 3; ++ch) {
        double got = 0.0, exact = 0.0, var = 0.0;
        for (int j = 0; j < cam.height / 4; ++j) {
            for (int i = 0; i < cam.width / 4; ++i) {
                const double g = testing::bin_sum(pt.layers.backscatter, i, j, ch, 4);
                const double e = testing::bin_sum(want, i, j, ch, 4);
                const double v = testing::bin_sum(pt.std_error.backscatter, i, j, ch, 4, true);
                worst = std::max(worst, std::fabs(g - e) / std::sqrt(v));
                EXPECT_LE(std::fabs(g - e), 4.0 * std::sqrt(v))
                    << "order " << order << " bin (" << i << ", " << j << ") ch " << ch;
                got += g;
                exact += e;
                var += v;
            }
        }
        std::printf("order %d, channel %d: image sum %.6g, integral %.6g (%+.3f %%, %.2f SE)\n",
                    order, ch, got, exact, 100.0 * (got / exact - 1.0),
                    (got - exact) / std::sqrt(var));
        EXPECT_LE(std::fabs(got - exact), 3.0 * std::sqrt(var)) << "channel " << ch;
        EXPECT_LE(std::sqrt(var), 0.02 * exact) << "too noisy to tell";
    }
    std::printf("order %d: worst 4x4 bin %.2f SE\n", order, worst);
}

TEST(PathTracerOrders, OrderTwoMatchesTheRadialIntegral) { expect_order(2); }

TEST(PathTracerOrders, OrderThreeMatchesTheRadialIntegral) { expect_order(3); }

}  // namespace

}  // namespace deepsea
