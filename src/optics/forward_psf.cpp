#include "deepsea/optics/forward_psf.h"

#include <algorithm>
#include <cmath>

#include "deepsea/optics/forward.h"
#include "deepsea/optics/water.h"

namespace deepsea {

namespace {

constexpr double kHalfPi = M_PI / 2.0;
constexpr double kSigma0 = 1e-5;                ///< narrowest mixture width, radians
constexpr double kStep = 1.189207115002721;     ///< 2^(1/4) between mixture widths
constexpr int kWidths = 72;                     ///< 1e-5 .. 2.6 rad
constexpr double kMedian = 1.1774100225154747;  ///< median radius of a 2-D Gaussian / sigma

/// P(t) = integral_t^{pi/2} p(theta) sin(theta) / theta dtheta and the enclosed share
/// E(t) = 2 pi integral_0^t P, tabulated on a grid logarithmic from 1e-8 rad (trapezoids).
struct KernelTable {
    std::vector<double> t, P, E;

    explicit KernelTable(const Phase& phase) {
        const int n = 6000;
        const double a = 1e-8;
        t.resize(n + 1);
        t[0] = 0.0;
        for (int i = 1; i <= n; ++i) t[i] = a * std::pow(kHalfPi / a, double(i - 1) / (n - 1));
        const auto f = [&](double th) {
            return phase(std::cos(th)) * (th > 0.0 ? std::sin(th) / th : 1.0);
        };
        P.assign(n + 1, 0.0);
        double f_hi = f(t[n]);
        for (int i = n - 1; i >= 0; --i) {
            const double f_lo = f(t[i]);
            P[i] = P[i + 1] + 0.5 * (f_lo + f_hi) * (t[i + 1] - t[i]);
            f_hi = f_lo;
        }
        E.assign(n + 1, 0.0);
        for (int i = 1; i <= n; ++i) E[i] = E[i - 1] + M_PI * (P[i - 1] + P[i]) * (t[i] - t[i - 1]);
    }
    /// Linear interpolation of a tabulated column at psi (clamped to [0, pi/2]).
    double at(const std::vector<double>& col, double psi) const {
        psi = std::clamp(psi, 0.0, kHalfPi);
        const auto it = std::upper_bound(t.begin(), t.end(), psi);
        const std::size_t i =
            std::min<std::size_t>(std::max<std::ptrdiff_t>(it - t.begin(), 1), t.size() - 1);
        const double w = (psi - t[i - 1]) / (t[i] - t[i - 1]);
        return col[i - 1] + w * (col[i] - col[i - 1]);
    }
};

/// Where a weight at width sigma goes on a grid of widths: 1 - f of it to width lo, f to hi
/// (linear in log sigma between the two widths around sigma; all to the end width beyond
/// either end).
struct Placement {
    std::size_t lo = 0, hi = 0;
    double f = 0.0;
};
Placement placement(const std::vector<double>& grid, double sigma) {
    const std::size_t n = grid.size();
    if (sigma <= grid.front()) return {0, 0, 0.0};
    if (sigma >= grid.back()) return {n - 1, n - 1, 0.0};
    const std::size_t k = std::upper_bound(grid.begin(), grid.end(), sigma) - grid.begin() - 1;
    return {k, std::min(k + 1, n - 1), std::log(sigma / grid[k]) / std::log(grid[k + 1] / grid[k])};
}

/// Adds weight w at width sigma to the grid's widths (placement).
void add_placed(const Placement& p, double w, std::vector<double>& out) {
    out[p.lo] += w * (1.0 - p.f);
    out[p.hi] += w * p.f;
}
void place(const std::vector<double>& grid, double sigma, double w, std::vector<double>& out) {
    add_placed(placement(grid, sigma), w, out);
}

}  // namespace

double forward_kernel(const Phase& phase, double psi) {
    if (!(psi > 0.0) || psi > kHalfPi) return 0.0;
    const KernelTable table(phase);
    return table.at(table.P, psi) / psi;
}

double forward_kernel_within(const Phase& phase, double psi) {
    const KernelTable table(phase);
    return table.at(table.E, psi);
}

ForwardSpread forward_spread(const Phase& phase, int orders) {
    const KernelTable table(phase);
    ForwardSpread s;
    s.sigma.resize(kWidths);
    for (int j = 0; j < kWidths; ++j) s.sigma[j] = kSigma0 * std::pow(kStep, j);
    // K_1: mixture weights fitted to the kernel's share on 480 rings (log-spaced radii up to
    // pi/2) by expectation-maximisation, which keeps them non-negative and their sum exact;
    // started from the ring between neighbouring median radii of each width.
    const int rings = 480;
    std::vector<double> edge(rings + 1), target(rings);
    edge[0] = 0.0;
    for (int i = 1; i <= rings; ++i)
        edge[i] = 1e-7 * std::pow(kHalfPi / 1e-7, double(i - 1) / (rings - 1));
    for (int i = 0; i < rings; ++i)
        target[i] = table.at(table.E, edge[i + 1]) - table.at(table.E, edge[i]);
    // share of width j on ring i (the last ring reaches to infinity)
    std::vector<double> share(std::size_t(kWidths) * rings);
    for (int j = 0; j < kWidths; ++j) {
        for (int i = 0; i < rings; ++i) {
            const auto out = [&](double r) {
                return std::exp(-0.5 * r * r / (s.sigma[j] * s.sigma[j]));
            };
            share[std::size_t(j) * rings + i] =
                out(edge[i]) - (i + 1 < rings ? out(edge[i + 1]) : 0.0);
        }
    }
    std::vector<double> first(kWidths, 0.0);
    double below = 0.0;
    const double half_step = std::sqrt(kStep);
    for (int j = 0; j < kWidths; ++j) {
        const double e = j + 1 < kWidths ? kMedian * s.sigma[j] * half_step : kHalfPi;
        const double within = table.at(table.E, e);
        first[j] = std::max(within - below, 1e-12);
        below = within;
    }
    std::vector<double> model(rings), ratio(rings), next(kWidths);
    for (int iter = 0; iter < 400; ++iter) {
        std::fill(model.begin(), model.end(), 0.0);
        for (int j = 0; j < kWidths; ++j) {
            for (int i = 0; i < rings; ++i)
                model[i] += first[j] * share[std::size_t(j) * rings + i];
        }
        // each ring's target over its model, once a ring rather than once a ring and width
        for (int i = 0; i < rings; ++i) ratio[i] = model[i] > 0.0 ? target[i] / model[i] : 0.0;
        // four widths' sums side by side, each over the rings in order (independent chains)
        static_assert(kWidths % 4 == 0, "widths in fours");
        for (int j = 0; j < kWidths; j += 4) {
            const double* s0 = &share[std::size_t(j) * rings];
            double sum[4] = {};
            for (int i = 0; i < rings; ++i) {
                for (int m = 0; m < 4; ++m) sum[m] += ratio[i] * s0[std::size_t(m) * rings + i];
            }
            for (int m = 0; m < 4; ++m) next[j + m] = first[j + m] * sum[m];
        }
        first.swap(next);
    }
    // K_{n+1} = K_n * K_1: Gaussians convolve by adding variances. Where each pair of widths
    // lands is the same for every order: found once.
    std::vector<Placement> pair(std::size_t(kWidths) * kWidths);
    for (int i = 0; i < kWidths; ++i) {
        for (int k = 0; k < kWidths; ++k)
            pair[std::size_t(i) * kWidths + k] =
                placement(s.sigma, std::hypot(s.sigma[i], s.sigma[k]));
    }
    s.mass.assign(std::max(orders, 1), std::vector<double>(kWidths, 0.0));
    s.mass[0] = first;
    for (int n = 1; n < orders; ++n) {
        const std::vector<double>& prev = s.mass[n - 1];
        std::vector<double>& next = s.mass[n];
        for (int i = 0; i < kWidths; ++i) {
            if (prev[i] < 1e-300) continue;
            for (int k = 0; k < kWidths; ++k) {
                if (first[k] <= 0.0) continue;
                add_placed(pair[std::size_t(i) * kWidths + k], prev[i] * first[k], next);
            }
        }
    }
    return s;
}

double mixture_within(const std::vector<double>& sigma, const std::vector<double>& mass,
                      double psi) {
    double sum = 0.0;
    for (std::size_t j = 0; j < sigma.size(); ++j) {
        sum += mass[j] * (1.0 - std::exp(-0.5 * psi * psi / (sigma[j] * sigma[j])));
    }
    return sum;
}

ForwardPsf::ForwardPsf(const Water& water, double fx, int width, int height)
    : m_c(water.c), m_b(water.b) {
    const double cap = max_forward_sigma_px(width, height);
    m_sigma_px = {0.0};
    for (double s = 1.0; s < cap; s *= 2.0) m_sigma_px.push_back(s);
    m_sigma_px.push_back(cap);
    const std::vector<double> blurred(m_sigma_px.begin() + 1, m_sigma_px.end());
    const ForwardSpread spread = forward_spread(water.phase);
    for (const double m : spread.mass[0]) m_forward += m;
    m_mass.assign(spread.mass.size(), std::vector<double>(m_sigma_px.size(), 0.0));
    for (std::size_t n = 0; n < spread.mass.size(); ++n) {
        std::vector<double> on_blurred(blurred.size(), 0.0);
        for (std::size_t i = 0; i < spread.sigma.size(); ++i) {
            const double w = spread.mass[n][i];
            if (w <= 0.0) continue;
            const double s = fx * spread.sigma[i];
            if (s < 1.0) {
                // below a pixel: unblurred and 1 px in the proportion that keeps the variance
                m_mass[n][0] += w * (1.0 - s * s);
                on_blurred[0] += w * s * s;
            } else {
                place(blurred, s, w, on_blurred);
            }
        }
        for (std::size_t j = 0; j < blurred.size(); ++j) m_mass[n][j + 1] += on_blurred[j];
    }
}

Rgb ForwardPsf::weight(int j, double d) const {
    Rgb out;
    for (int ch = 0; ch < 3; ++ch) {
        const double bd = m_b[ch] * d;
        double term = std::exp(-m_c[ch] * d), terms = term, sum = 0.0;
        for (std::size_t n = 1; n <= m_mass.size(); ++n) {
            term *= bd / double(n);
            terms += term;
            sum += term * m_mass[n - 1][j];
            if (double(n) > bd && term <= 1e-13 * terms) break;
        }
        out[ch] = sum;
    }
    return out;
}

double ForwardPsf::negligible_beyond() const {
    double rate = 1e300;
    for (int ch = 0; ch < 3; ++ch) rate = std::min(rate, m_c[ch] - m_forward * m_b[ch]);
    return rate > 0.0 ? std::min(40.0 / rate, 1e7) : 1e7;
}

Rgb ForwardPsf::total(double d) const {
    Rgb sum;
    for (int j = 0; j < scales(); ++j) sum += weight(j, d);
    return sum;
}

}  // namespace deepsea
