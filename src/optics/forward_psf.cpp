#include "deepsea/optics/forward_psf.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "deepsea/optics/forward.h"
#include "deepsea/optics/forward_transport.h"
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

typedef double Double4 __attribute__((vector_size(32)));

// An AVX2 clone of the fit's iterations where the CPU has it (the fit is most of a compositor's
// making): AVX2 without FMA, so that each product and sum rounds as the generic clone's does and
// the weights are the same bits on every x86-64.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(DEEPSEA_NO_CLONES)
#define DEEPSEA_FIT_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define DEEPSEA_FIT_CLONES
#endif

/// `iterations` steps of expectation-maximisation: `first` (W weights) times, for each width,
/// the sum over the R rings of its share times the ring's target over the model. `share` is
/// [j * R + i], `share4` the same four widths to a ring ([((j / 4) * R + i) * 4 + j % 4]);
/// `model`, `ratio` (R) and `next` (W) are scratch.
DEEPSEA_FIT_CLONES
void em_iterations(int W, int R, int iterations, const double* share, const double* share4,
                   const double* target, double* first, double* model, double* ratio,
                   double* next) {
    for (int iter = 0; iter < iterations; ++iter) {
        // model[i] = sum over widths j in order of first[j] share(j, i), four widths a pass
        std::fill(model, model + R, 0.0);
        for (int j = 0; j < W; j += 4) {
            const double* s0 = share + std::size_t(j) * R;
            const double f0 = first[j], f1 = first[j + 1], f2 = first[j + 2], f3 = first[j + 3];
            for (int i = 0; i < R; ++i) {
                model[i] = model[i] + f0 * s0[i] + f1 * s0[R + i] + f2 * s0[2 * R + i] +
                           f3 * s0[3 * R + i];
            }
        }
        // each ring's target over its model, once a ring rather than once a ring and width
        for (int i = 0; i < R; ++i) ratio[i] = model[i] > 0.0 ? target[i] / model[i] : 0.0;
        // four widths' sums side by side, the lanes of a vector, each over the rings in order
        // (independent chains: each lane's sum is the scalar loop's, bit for bit)
        for (int j = 0; j < W; j += 4) {
            const double* s0 = share4 + std::size_t(j) * R;
            Double4 sum = {};
            for (int i = 0; i < R; ++i) {
                Double4 s;
                std::memcpy(&s, s0 + std::size_t(i) * 4, sizeof s);
                sum += ratio[i] * s;
            }
            for (int m = 0; m < 4; ++m) next[j + m] = first[j + m] * sum[m];
        }
        std::copy(next, next + W, first);
    }
}

/// Gaussian mixtures on fixed widths fitted to shares on rings [edge[i], edge[i + 1]) (the
/// last ring reaching to infinity) by expectation-maximisation, which keeps the weights
/// non-negative and their sum that of the shares.
class RingFit {
public:
    RingFit(const std::vector<double>& sigma, const std::vector<double>& edge)
        : m_widths(int(sigma.size())), m_rings(int(edge.size()) - 1) {
        m_share.resize(std::size_t(m_widths) * m_rings);
        for (int j = 0; j < m_widths; ++j) {
            for (int i = 0; i < m_rings; ++i) {
                const auto out = [&](double r) {
                    return std::exp(-0.5 * r * r / (sigma[j] * sigma[j]));
                };
                m_share[std::size_t(j) * m_rings + i] =
                    out(edge[i]) - (i + 1 < m_rings ? out(edge[i + 1]) : 0.0);
            }
        }
        // the same shares four widths to a ring, as fit's sums read them
        m_share4.resize(m_share.size());
        for (int j = 0; j < m_widths; ++j) {
            for (int i = 0; i < m_rings; ++i) {
                m_share4[(std::size_t(j / 4) * m_rings + i) * 4 + j % 4] =
                    m_share[std::size_t(j) * m_rings + i];
            }
        }
    }
    /// Share of width j on ring i.
    double share(int j, int i) const { return m_share[std::size_t(j) * m_rings + i]; }
    /// Weights on the widths for ring shares `target`, from the positive start `first`.
    std::vector<double> fit(const std::vector<double>& target, std::vector<double> first,
                            int iterations = 400) const {
        static_assert(kWidths % 4 == 0, "widths in fours");
        std::vector<double> model(m_rings), ratio(m_rings), next(m_widths);
        em_iterations(m_widths, m_rings, iterations, m_share.data(), m_share4.data(), target.data(),
                      first.data(), model.data(), ratio.data(), next.data());
        return first;
    }

private:
    int m_widths, m_rings;
    std::vector<double> m_share;   ///< [j * rings + i]
    std::vector<double> m_share4;  ///< [((j / 4) * rings + i) * 4 + j % 4]
};

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
    // pi/2), started from the ring between neighbouring median radii of each width.
    const int rings = 480;
    std::vector<double> edge(rings + 1), target(rings);
    edge[0] = 0.0;
    for (int i = 1; i <= rings; ++i)
        edge[i] = 1e-7 * std::pow(kHalfPi / 1e-7, double(i - 1) / (rings - 1));
    for (int i = 0; i < rings; ++i)
        target[i] = table.at(table.E, edge[i + 1]) - table.at(table.E, edge[i]);
    std::vector<double> first(kWidths, 0.0);
    double below = 0.0;
    const double half_step = std::sqrt(kStep);
    for (int j = 0; j < kWidths; ++j) {
        const double e = j + 1 < kWidths ? kMedian * s.sigma[j] * half_step : kHalfPi;
        const double within = table.at(table.E, e);
        first[j] = std::max(within - below, 1e-12);
        below = within;
    }
    first = RingFit(s.sigma, edge).fit(target, std::move(first));
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

namespace {

/// The pixel scales of a camera: 0 (unblurred), then 1, 2, 4, ... px up to the cap.
std::vector<double> pixel_scales(int width, int height) {
    const double cap = max_forward_sigma_px(width, height);
    std::vector<double> px = {0.0};
    for (double s = 1.0; s < cap; s *= 2.0) px.push_back(s);
    px.push_back(cap);
    return px;
}

/// Adds a mixture on angular widths (radians) to weights on pixel scales (`scales`, scale 0
/// unblurred): widths below a pixel split between unblurred and 1 px in the proportion that
/// keeps the variance, wider ones placed between the two scales around them.
void add_on_pixels(const std::vector<double>& sigma, const std::vector<double>& mass, double fx,
                   const std::vector<double>& scales, double* out) {
    const std::vector<double> blurred(scales.begin() + 1, scales.end());
    std::vector<double> on_blurred(blurred.size(), 0.0);
    for (std::size_t i = 0; i < sigma.size(); ++i) {
        const double w = mass[i];
        if (w <= 0.0) continue;
        const double s = fx * sigma[i];
        if (s < 1.0) {
            out[0] += w * (1.0 - s * s);
            on_blurred[0] += w * s * s;
        } else {
            place(blurred, s, w, on_blurred);
        }
    }
    for (std::size_t j = 0; j < blurred.size(); ++j) out[j + 1] += on_blurred[j];
}

std::vector<double> mixture_widths() {
    std::vector<double> sigma(kWidths);
    for (int j = 0; j < kWidths; ++j) sigma[j] = kSigma0 * std::pow(kStep, j);
    return sigma;
}

/// forward_spread(phase), fitted once a process for each phase (as the Petzold tables are
/// normalised once): a pure function of the phase, and most of the making of every compositor of
/// a water with it.
std::shared_ptr<const ForwardSpread> fitted_spread(const Phase& phase) {
    static std::mutex mutex;
    static std::map<std::pair<int, double>, std::shared_ptr<const ForwardSpread>> fitted;
    const std::lock_guard<std::mutex> lock(mutex);
    std::shared_ptr<const ForwardSpread>& s = fitted[{int(phase.kind), phase.g}];
    if (!s) s = std::make_shared<const ForwardSpread>(forward_spread(phase));
    return s;
}

}  // namespace

ForwardPsf::ForwardPsf(const Water& water, double fx, int width, int height)
    : m_c(water.c), m_b(water.b) {
    m_sigma_px = pixel_scales(width, height);
    const std::shared_ptr<const ForwardSpread> spread = fitted_spread(water.phase);
    for (const double m : spread->mass[0]) m_forward += m;
    m_mass.assign(spread->mass.size(), std::vector<double>(m_sigma_px.size(), 0.0));
    for (std::size_t n = 0; n < spread->mass.size(); ++n)
        add_on_pixels(spread->sigma, spread->mass[n], fx, m_sigma_px, m_mass[n].data());
}

ForwardPsf::ForwardPsf(const ForwardPsfTable& table, const Water& water, double fx, int width,
                       int height)
    : m_c(water.c), m_b(water.b), m_table(true) {
    table.validate("forward scatter table");
    m_sigma_px = pixel_scales(width, height);
    m_forward = forward_kernel_within(water.phase, kHalfPi);
    const std::vector<double> sigma = mixture_widths();
    const RingFit fit(sigma, table.ring_edge);
    const int K = table.depths(), R = table.rings(), S = scales();
    // The table holds what a pixel gathers from a plane at depth d; a surface point seen at
    // range r sends a pixel psi away what the plane at depth r cos(psi) sends it (the same
    // point): resampled per ring, linear in depth between the table's, 0 at depth 0.
    const auto gathered = [&](int i, double d, int c) {
        const std::vector<double>& z = table.depth;
        if (d <= 0.0) return 0.0;
        const std::size_t k = std::size_t(std::upper_bound(z.begin(), z.end(), d) - z.begin());
        const auto at = [&](std::size_t m) { return table.share[m * R + i][c]; };
        if (k == 0) return at(0) * d / z[0];
        if (k >= z.size()) return at(z.size() - 1);
        const double f = (d - z[k - 1]) / (z[k] - z[k - 1]);
        return at(k - 1) + f * (at(k) - at(k - 1));
    };
    m_node = table.depth;
    m_node_weight.assign(std::size_t(K) * S, Rgb());
    std::vector<double> target(R), cum_fit(R + 1);
    for (int k = 0; k < K; ++k) {
        for (int c = 0; c < 3; ++c) {
            double total = 0.0;
            for (int i = 0; i < R; ++i) {
                const double psi = i == 0 ? 0.5 * table.ring_edge[1]
                                          : std::sqrt(table.ring_edge[i] * table.ring_edge[i + 1]);
                target[i] = gathered(i, table.depth[k] * std::cos(psi), c);
                total += target[i];
            }
            if (!(total > 0.0)) continue;
            std::vector<double> first(kWidths, total / kWidths);
            const std::vector<double> mass = fit.fit(target, std::move(first));
            // how far the mixture's enclosed share strays from the table's, at any ring edge
            // but the last (the fit's last ring reaches to infinity)
            double table_cum = 0.0, worst = 0.0;
            for (int i = 0; i + 1 < R; ++i) {
                table_cum += target[i];
                double model = 0.0;
                for (int j = 0; j < kWidths; ++j) {
                    const double r = table.ring_edge[i + 1];
                    model += mass[j] * (1.0 - std::exp(-0.5 * r * r / (sigma[j] * sigma[j])));
                }
                worst = std::max(worst, std::abs(model - table_cum) / total);
            }
            m_fit_error = std::max(m_fit_error, worst);
            std::vector<double> px(S, 0.0);
            add_on_pixels(sigma, mass, fx, m_sigma_px, px.data());
            for (int j = 0; j < S; ++j) m_node_weight[std::size_t(k) * S + j][c] = px[j];
        }
    }
    // Beyond the last depth the weights keep their shape and fall as the total did between
    // the last two depths (at least as fast as exp(-(c - b) d), at most as exp(-c d)).
    for (int c = 0; c < 3; ++c) {
        double rate = m_c[c];
        if (K >= 2) {
            double t0 = 0.0, t1 = 0.0;
            for (int j = 0; j < S; ++j) {
                t0 += m_node_weight[std::size_t(K - 2) * S + j][c];
                t1 += m_node_weight[std::size_t(K - 1) * S + j][c];
            }
            if (t0 > 0.0 && t1 > 0.0) rate = std::log(t0 / t1) / (m_node[K - 1] - m_node[K - 2]);
        }
        m_tail_rate[c] = std::clamp(rate, m_c[c] - m_b[c], m_c[c]);
    }
}

Rgb ForwardPsf::weight(int j, double d) const {
    Rgb out;
    if (m_table) {
        if (!(d > 0.0)) return out;
        const int S = scales(), K = int(m_node.size());
        const auto w = [&](int k) { return m_node_weight[std::size_t(k) * S + j]; };
        const std::size_t k =
            std::size_t(std::upper_bound(m_node.begin(), m_node.end(), d) - m_node.begin());
        if (k == 0) return w(0) * (d / m_node[0]);
        if (k >= std::size_t(K)) return w(K - 1) * exp(m_tail_rate * -(d - m_node[K - 1]));
        const double f = (d - m_node[k - 1]) / (m_node[k] - m_node[k - 1]);
        return w(int(k) - 1) * (1.0 - f) + w(int(k)) * f;
    }
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
    for (int ch = 0; ch < 3; ++ch)
        rate = std::min(rate, m_table ? m_tail_rate[ch] : m_c[ch] - m_forward * m_b[ch]);
    if (m_table && !m_node.empty())
        return std::min(m_node.back() + 40.0 / std::max(rate, 1e-7), 1e7);
    return rate > 0.0 ? std::min(40.0 / rate, 1e7) : 1e7;
}

Rgb ForwardPsf::total(double d) const {
    Rgb sum;
    for (int j = 0; j < scales(); ++j) sum += weight(j, d);
    return sum;
}

}  // namespace deepsea
