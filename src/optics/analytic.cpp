#include "deepsea/optics/analytic.h"

#include <cmath>

#include "quadrature.h"

namespace deepsea {

namespace {

/// Sun et al.'s special function F(A, xi) = integral_0^xi exp(-A tan(eta)) d eta, by adaptive
/// Gauss-Kronrod to 1e-13 relative (the paper tabulates it; it has no elementary form).
double sun_F(double A, double xi) {
    const auto f = [A](double eta) { return std::exp(-A * std::tan(eta)); };
    const auto absdiff = [](double a, double b) { return std::fabs(a - b); };
    double total = 0.0;
    struct Panel {
        double a, b;
        int depth;
    };
    Panel stack[128];
    int top = 0;
    stack[top++] = {0.0, xi, 0};
    while (top > 0) {
        const Panel p = stack[--top];
        double k, e;
        detail::gk15<double>(f, p.a, p.b, k, e, absdiff);
        if (e <= 1e-14 * std::max(std::fabs(k), 1e-300) * 1e3 || p.depth > 50 || top > 120) {
            total += k;
        } else {
            const double m = 0.5 * (p.a + p.b);
            stack[top++] = {p.a, m, p.depth + 1};
            stack[top++] = {m, p.b, p.depth + 1};
        }
    }
    return total;
}

}  // namespace

double sun2005_airlight(double c, double b, double I0, double d_sv, double gamma, double d_vp) {
    // Sun et al. write the medium with one coefficient beta for both scattering and
    // extinction. Scattering only enters as the prefactor of the single-scattering integral
    // (b / 4 pi), so with extinction c the airlight is (b / c) times theirs with beta = c.
    const double T_sv = c * d_sv, T_vp = c * d_vp;
    const double A1 = T_sv * std::sin(gamma);
    const double A0 = c * c * I0 * std::exp(-T_sv * std::cos(gamma)) / (2.0 * M_PI * A1);
    const double xi1 = M_PI / 4.0 + 0.5 * std::atan((T_vp - T_sv * std::cos(gamma)) / A1);
    const double La = A0 * (sun_F(A1, xi1) - sun_F(A1, gamma / 2.0));
    return (b / c) * La;
}

}  // namespace deepsea
