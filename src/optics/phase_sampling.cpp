#include "deepsea/optics/phase_sampling.h"

#include <algorithm>
#include <cmath>

namespace deepsea {

namespace {

bool tabulated(PhaseKind k) {
    return k != PhaseKind::Isotropic && k != PhaseKind::HenyeyGreenstein;
}

}  // namespace

namespace {

/// Angles 0 .. pi: logarithmic below 0.1 rad (the forward peak of measured phase functions),
/// uniform after.
std::vector<double> angle_grid(int n_log, int n_lin) {
    std::vector<double> psi{0.0};
    const double a = 1e-6, b = 0.1;
    for (int i = 0; i < n_log; ++i) psi.push_back(a * std::pow(b / a, double(i) / n_log));
    for (int i = 0; i <= n_lin; ++i) psi.push_back(b + (M_PI - b) * i / n_lin);
    return psi;
}

}  // namespace

PhaseSampler::PhaseSampler(const Phase& phase) : m_phase(phase) {
    m_grid = angle_grid(400, 1200);
    m_acdf.assign(m_grid.size(), 0.0);
    for (std::size_t i = 1; i < m_grid.size(); ++i) {
        const double pa = m_phase(std::cos(m_grid[i - 1])), pb = m_phase(std::cos(m_grid[i]));
        m_acdf[i] = m_acdf[i - 1] + 0.5 * (pa + pb) * (m_grid[i] - m_grid[i - 1]);
    }
    if (!tabulated(phase.kind)) return;
    m_psi = angle_grid(2000, 6000);
    m_cdf.assign(m_psi.size(), 0.0);
    const auto f = [&](double psi) { return 2.0 * M_PI * m_phase(std::cos(psi)) * std::sin(psi); };
    for (std::size_t i = 1; i < m_psi.size(); ++i) {
        m_cdf[i] = m_cdf[i - 1] + 0.5 * (f(m_psi[i - 1]) + f(m_psi[i])) * (m_psi[i] - m_psi[i - 1]);
    }
    const double total = m_cdf.back();
    for (double& c : m_cdf) c /= total;
}

double PhaseSampler::sample_cos(double u, double& weight) const {
    weight = 1.0;
    switch (m_phase.kind) {
        case PhaseKind::Isotropic:
            return 1.0 - 2.0 * u;
        case PhaseKind::HenyeyGreenstein: {
            const double g = m_phase.g;
            if (std::fabs(g) < 1e-4) return 1.0 - 2.0 * u;
            // Inversion of the HG cumulative distribution in cos(psi).
            const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
            return std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
        }
        default:
            break;
    }
    // Tabulated: psi uniform within the table interval that u falls in (density constant in
    // psi there), weight = p / pdf over the sphere, so the estimate stays unbiased.
    const auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), u);
    const std::size_t i =
        std::clamp<std::size_t>(std::size_t(it - m_cdf.begin()), 1, m_cdf.size() - 1);
    const double c0 = m_cdf[i - 1], c1 = m_cdf[i];
    const double w = c1 > c0 ? (u - c0) / (c1 - c0) : 0.5;
    const double psi = m_psi[i - 1] + w * (m_psi[i] - m_psi[i - 1]);
    const double pdf_psi = (c1 - c0) / (m_psi[i] - m_psi[i - 1]);
    const double s = std::sin(psi);
    const double cos_psi = std::cos(psi);
    weight = s > 0.0 && pdf_psi > 0.0 ? m_phase(cos_psi) * 2.0 * M_PI * s / pdf_psi : 1.0;
    return cos_psi;
}

double PhaseSampler::angle_cdf(double psi) const {
    psi = std::clamp(psi, 0.0, M_PI);
    const auto it = std::upper_bound(m_grid.begin(), m_grid.end(), psi);
    const std::size_t i =
        std::clamp<std::size_t>(std::size_t(it - m_grid.begin()), 1, m_grid.size() - 1);
    const double w = (psi - m_grid[i - 1]) / (m_grid[i] - m_grid[i - 1]);
    return m_acdf[i - 1] + w * (m_acdf[i] - m_acdf[i - 1]);
}

double PhaseSampler::angle_mass(double psi_a, double psi_b) const {
    return angle_cdf(psi_b) - angle_cdf(psi_a);
}

double PhaseSampler::angle_density(double psi) const {
    psi = std::clamp(psi, 0.0, M_PI);
    const auto it = std::upper_bound(m_grid.begin(), m_grid.end(), psi);
    const std::size_t i =
        std::clamp<std::size_t>(std::size_t(it - m_grid.begin()), 1, m_grid.size() - 1);
    return (m_acdf[i] - m_acdf[i - 1]) / (m_grid[i] - m_grid[i - 1]);
}

double PhaseSampler::sample_angle(double psi_a, double psi_b, double u) const {
    const double target = angle_cdf(psi_a) + u * angle_mass(psi_a, psi_b);
    const auto it = std::upper_bound(m_acdf.begin(), m_acdf.end(), target);
    const std::size_t i =
        std::clamp<std::size_t>(std::size_t(it - m_acdf.begin()), 1, m_acdf.size() - 1);
    const double c0 = m_acdf[i - 1], c1 = m_acdf[i];
    const double w = c1 > c0 ? (target - c0) / (c1 - c0) : 0.5;
    return std::clamp(m_grid[i - 1] + w * (m_grid[i] - m_grid[i - 1]), psi_a, psi_b);
}

double PhaseSampler::pdf(double cos_psi) const {
    if (m_psi.empty()) return m_phase(cos_psi);
    const double psi = std::acos(std::clamp(cos_psi, -1.0, 1.0));
    const auto it = std::upper_bound(m_psi.begin(), m_psi.end(), psi);
    const std::size_t i =
        std::clamp<std::size_t>(std::size_t(it - m_psi.begin()), 1, m_psi.size() - 1);
    const double pdf_psi = (m_cdf[i] - m_cdf[i - 1]) / (m_psi[i] - m_psi[i - 1]);
    return pdf_psi / (2.0 * M_PI * std::max(std::sin(psi), 1e-300));
}

PhaseSample PhaseSampler::sample(const Vec3& from, double u1, double u2) const {
    PhaseSample out;
    const double cos_psi = sample_cos(u1, out.weight);
    out.direction = rotate_about(from, cos_psi, 2.0 * M_PI * u2);
    return out;
}

Vec3 rotate_about(const Vec3& a, double cos_psi, double phi) {
    // Orthonormal basis around a without a branch on the axis (Duff et al. 2017).
    const double sign = std::copysign(1.0, a.z);
    const double p = -1.0 / (sign + a.z);
    const double q = a.x * a.y * p;
    const Vec3 t1(1.0 + sign * a.x * a.x * p, sign * q, -sign * a.x);
    const Vec3 t2(q, sign + a.y * a.y * p, -a.y);
    const double sin_psi = std::sqrt(std::max(0.0, 1.0 - cos_psi * cos_psi));
    return a * cos_psi + t1 * (sin_psi * std::cos(phi)) + t2 * (sin_psi * std::sin(phi));
}

}  // namespace deepsea
