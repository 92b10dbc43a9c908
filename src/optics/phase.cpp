#include "deepsea/optics/phase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace deepsea {

namespace {

#include "petzold_table.inc"

constexpr int kPetzoldRows = int(sizeof(kPetzold) / sizeof(kPetzold[0]));
constexpr double kDeg = M_PI / 180.0;

/// Petzold beta(psi) as tabulated, interpolated linearly in log(beta) against log(psi).
/// Below the first angle (0.1 deg) it is held at the 0.1 deg value: the measurement says
/// nothing there, and a power-law extrapolation (exponent -1.2 to -1.5) would put 5-12 % of
/// all scattering into that unmeasured cone and make p unbounded.
double petzold_raw(int col, double psi) {
    const double deg = psi / kDeg;
    if (deg <= kPetzold[0][0]) return kPetzold[0][col];
    int i = 1;
    while (i < kPetzoldRows - 1 && kPetzold[i][0] < deg) ++i;
    const double x0 = std::log(kPetzold[i - 1][0]), x1 = std::log(kPetzold[i][0]);
    const double w = (std::log(deg) - x0) / (x1 - x0);
    return std::exp((1.0 - w) * std::log(kPetzold[i - 1][col]) + w * std::log(kPetzold[i][col]));
}

/// Integral over the sphere of f(psi) * p(psi), p given as a function of psi (radians):
/// 2 pi * integral_0^pi f p sin(psi) dpsi, trapezoid on a grid that is logarithmic up to
/// 0.1 rad (the forward peak) and uniform after, plus the bounded tail below 1e-7 rad.
double sphere_integral(const std::function<double(double)>& p,
                       const std::function<double(double)>& f) {
    std::vector<double> x;
    const int n_log = 4000, n_lin = 40000;
    const double a = 1e-7, b = 0.1;
    for (int i = 0; i < n_log; ++i) x.push_back(a * std::pow(b / a, double(i) / n_log));
    for (int i = 0; i <= n_lin; ++i) x.push_back(b + (M_PI - b) * i / n_lin);
    double sum = 0.0;
    double prev = f(x[0]) * p(x[0]) * std::sin(x[0]);
    sum += prev * a / 2.0;  // tail [0, a]: p is constant there, sin(psi) ~ psi
    for (std::size_t i = 1; i < x.size(); ++i) {
        const double cur = f(x[i]) * p(x[i]) * std::sin(x[i]);
        sum += 0.5 * (prev + cur) * (x[i] - x[i - 1]);
        prev = cur;
    }
    return 2.0 * M_PI * sum;
}

/// A normalised Petzold phase function: exact log-log evaluation below 5 degrees, a dense
/// table (0.05 degree steps, linear) above, where the curve is smooth.
struct PetzoldPhase {
    double norm = 1.0;  ///< 1 / integral of beta over the sphere, sr^-1 ... (m)
    std::vector<double> table;
    static constexpr double kTableStart = 5.0 * kDeg;
    static constexpr double kTableStep = 0.05 * kDeg;
    int col = 1;
    double mean_cos = 0.0;
    double legendre2 = 0.0;  ///< integral of p P_2(cos psi) over the sphere

    explicit PetzoldPhase(int column) : col(column) {
        const auto raw = [column](double psi) { return petzold_raw(column, psi); };
        norm = 1.0 / sphere_integral(raw, [](double) { return 1.0; });
        const int n = int(std::ceil((M_PI - kTableStart) / kTableStep)) + 2;
        table.resize(n);
        for (int i = 0; i < n; ++i) {
            table[i] = norm * petzold_raw(column, std::min(kTableStart + i * kTableStep, M_PI));
        }
        mean_cos = sphere_integral([this](double psi) { return eval(psi); },
                                   [](double psi) { return std::cos(psi); });
        legendre2 = sphere_integral([this](double psi) { return eval(psi); },
                                    [](double psi) {
                                        const double c = std::cos(psi);
                                        return 0.5 * (3.0 * c * c - 1.0);
                                    });
    }
    double eval(double psi) const {
        if (psi < kTableStart) return norm * petzold_raw(col, psi);
        const double x = (psi - kTableStart) / kTableStep;
        const int i = std::min(int(x), int(table.size()) - 2);
        const double w = x - i;
        return table[i] + w * (table[i + 1] - table[i]);
    }
};

/// Each water's table made on its first use (three sphere integrals each), not all three at
/// once.
const PetzoldPhase& petzold(PhaseKind kind) {
    switch (kind) {
        case PhaseKind::PetzoldCoastal: {
            static const PetzoldPhase coastal(2);
            return coastal;
        }
        case PhaseKind::PetzoldTurbid: {
            static const PetzoldPhase turbid(3);
            return turbid;
        }
        default: {
            static const PetzoldPhase clear(1);
            return clear;
        }
    }
}

bool is_petzold(PhaseKind k) {
    return k == PhaseKind::PetzoldClear || k == PhaseKind::PetzoldCoastal ||
           k == PhaseKind::PetzoldTurbid;
}

}  // namespace

double Phase::operator()(double cos_psi) const {
    cos_psi = std::clamp(cos_psi, -1.0, 1.0);
    switch (kind) {
        case PhaseKind::Isotropic:
            return 1.0 / (4.0 * M_PI);
        case PhaseKind::HenyeyGreenstein:
            return henyey_greenstein(g, cos_psi);
        default:
            return petzold(kind).eval(std::acos(cos_psi));
    }
}

double Phase::mean_cosine() const {
    if (kind == PhaseKind::Isotropic) return 0.0;
    if (is_petzold(kind)) return petzold(kind).mean_cos;
    return sphere_integral([this](double psi) { return (*this)(std::cos(psi)); },
                           [](double psi) { return std::cos(psi); });
}

double Phase::fraction_within(double psi_max) const {
    const auto p = [this](double psi) {
        return is_petzold(kind) ? petzold(kind).eval(psi) : (*this)(std::cos(psi));
    };
    return sphere_integral(p, [psi_max](double psi) { return psi <= psi_max ? 1.0 : 0.0; });
}

double Phase::legendre_moment(int l) const {
    if (l < 0 || l > 2) throw std::invalid_argument("Phase::legendre_moment: l must be 0, 1 or 2");
    if (l == 0) return 1.0;
    if (kind == PhaseKind::Isotropic) return 0.0;
    if (kind == PhaseKind::HenyeyGreenstein) return l == 1 ? g : g * g;
    return l == 1 ? petzold(kind).mean_cos : petzold(kind).legendre2;
}

const char* to_string(PhaseKind kind) {
    switch (kind) {
        case PhaseKind::Isotropic:
            return "isotropic";
        case PhaseKind::HenyeyGreenstein:
            return "henyey_greenstein";
        case PhaseKind::PetzoldClear:
            return "petzold:clear";
        case PhaseKind::PetzoldCoastal:
            return "petzold:coastal";
        case PhaseKind::PetzoldTurbid:
            return "petzold:turbid";
    }
    return "unknown";
}

}  // namespace deepsea
