#include "deepsea/optics/multiple_scattering.h"

#include <algorithm>
#include <cmath>

#include "deepsea/optics/backscatter.h"

namespace deepsea {

namespace {

/// Below this throughput (relative to a path's start) Russian roulette decides.
constexpr double kRoulette = 0.1;

}  // namespace

Transport::Transport(const Rig& rig, const Water& water)
    : m_rig(rig), m_water(water), m_sampler(water.phase) {
    m_c_min = std::max(water.c.min(), 1e-6);
    m_far = std::log(1e6) / m_c_min;
    double w = 0.0;
    m_theta_p = std::clamp(std::acos(m_sampler.sample_cos(0.5, w)), 1e-3, M_PI);
}

Rgb Transport::segment_from_lamp(const Light& L, const Vec3& X, const Vec3& d, double u,
                                 double* z_at) const {
    // Equiangular parameter: r = delta + h tan(theta), dr = d1^2 / h dtheta, which cancels the
    // lamp's 1/d1^2. The scattering angle at the point is psi = pi/2 + theta exactly, so the
    // phase function is a function of theta alone: theta is drawn half the time uniformly,
    // half the time in proportion to p (one-sample MIS, balance heuristic).
    const Vec3 to_lamp = L.position - X;
    const double delta = dot(to_lamp, d);
    const double h = std::sqrt(std::max(dot(to_lamp, to_lamp) - delta * delta, 1e-18));
    const double ta = std::atan2(-delta, h), tb = std::atan2(m_far - delta, h);
    const double pa = 0.5 * M_PI + ta, pb = 0.5 * M_PI + tb;
    const double mass = m_sampler.angle_mass(pa, pb);
    double theta;
    if (u < 0.5 || !(mass > 0.0)) {
        theta = ta + 2.0 * u * (tb - ta);
    } else {
        theta = m_sampler.sample_angle(pa, pb, 2.0 * u - 1.0) - 0.5 * M_PI;
    }
    const double pdf_theta =
        0.5 / (tb - ta) +
        (mass > 0.0 ? 0.5 * m_sampler.angle_density(0.5 * M_PI + theta) / mass : 0.0);
    const double r = delta + h * std::tan(theta);
    if (!(r > 0.0) || !(pdf_theta > 0.0)) return {};
    if (z_at) *z_at = X.z + d.z * r;
    double d1 = 0.0;
    const Rgb s = lamp_in_scatter(L, m_water, X + d * r, -d, &d1);
    return s * exp(m_water.c * -r) * (d1 * d1 / (h * pdf_theta));
}

// The direction mixture: strategy 0 is the phase function about `from` (uniform without
// one); then, per lamp, two cones uniform in the angle theta to the lamp: one out to the phase
// function's median angle theta_p, one out to pi (densities 1 / (2 pi theta_max sin theta)).
// Looking almost straight at a point lamp, the once-scattered radiance grows as 1 / theta
// (the lamp's glow, for theta within the phase function's forward peak); uniform-in-angle
// sampling cancels that, which keeps the estimate's variance finite.
namespace {

constexpr double kFirst = 0.4;  ///< share of strategy 0; the lamps share the rest equally

/// Density 1/sr of directions uniform in their angle theta in [0, theta_max] to an axis,
/// cos(theta) = mu.
double uniform_angle_pdf(double mu, double theta_max) {
    if (mu < std::cos(theta_max)) return 0.0;
    const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    return 1.0 / (2.0 * M_PI * theta_max * std::max(s, 1e-300));
}

}  // namespace

double Transport::direction_pdf(const Vec3& X, const Vec3* from, const Vec3& d) const {
    const double q = (1.0 - kFirst) / (2.0 * double(m_rig.lights.size()));
    double pdf = kFirst * (from ? m_sampler.pdf(dot(*from, d)) : 1.0 / (4.0 * M_PI));
    for (const Light& L : m_rig.lights) {
        const Vec3 to = L.position - X;
        const double n = length(to);
        if (!(n > 0.0)) continue;
        const double mu = dot(to / n, d);
        pdf += q * (uniform_angle_pdf(mu, m_theta_p) + uniform_angle_pdf(mu, M_PI));
    }
    return pdf;
}

Vec3 Transport::sample_mixture(const Vec3& X, const Vec3* from, Rng& rng) const {
    const double u = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    const std::size_t n = m_rig.lights.size();
    if (u >= kFirst) {
        const double x = (u - kFirst) / (1.0 - kFirst) * double(2 * n);
        const std::size_t s = std::min(std::size_t(x), 2 * n - 1);
        const Vec3 to = m_rig.lights[s / 2].position - X;
        const double len = length(to);
        if (len > 0.0) {
            const double theta_max = s % 2 == 0 ? m_theta_p : M_PI;
            return rotate_about(to / len, std::cos(theta_max * u1), 2.0 * M_PI * u2);
        }
    }
    if (from) return m_sampler.sample(*from, u1, u2).direction;
    return rotate_about(Vec3(0, 0, 1), 1.0 - 2.0 * u1, 2.0 * M_PI * u2);
}

PhaseSample Transport::next_direction(const Vec3& X, const Vec3& from, Rng& rng) const {
    PhaseSample out;
    out.direction = sample_mixture(X, &from, rng);
    out.weight = m_water.phase(dot(from, out.direction)) / direction_pdf(X, &from, out.direction);
    return out;
}

PhaseSample Transport::any_direction(const Vec3& X, Rng& rng) const {
    PhaseSample out;
    out.direction = sample_mixture(X, nullptr, rng);
    out.weight = 1.0 / direction_pdf(X, nullptr, out.direction);
    return out;
}

Rgb Transport::scattered_radiance(Vec3 X, Vec3 d, Rng& rng) const {
    thread_local std::vector<std::pair<double, Rgb>> parts;  // reused: no allocation per path
    parts.clear();
    scattered_contributions(X, d, rng, parts);
    Rgb sum;
    for (const auto& p : parts) sum += p.second;
    return sum;
}

void Transport::scattered_contributions(Vec3 X, Vec3 d, Rng& rng,
                                        std::vector<std::pair<double, Rgb>>& out) const {
    Rgb weight(1.0);
    const Vec3 start = X;
    double z_max = X.z;  // the deepest the path has been
    for (;;) {
        // Light scattered once on this segment (next event, every lamp), with the weight the
        // path has: roulette comes after it. A direction drawn from a lamp's cone at a small
        // phase function value has a small weight and a segment that passes close to the lamp,
        // where the next event is largest; rouletted first, the few that survived carried that
        // next event multiplied by 1 / weight (one path 36455 x its column's mean).
        for (const Light& L : m_rig.lights) {
            double z = X.z;
            const Rgb s = segment_from_lamp(L, X, d, rng.uniform(), &z);
            if (s.max() > 0.0) out.emplace_back(std::max(z_max, z), weight * s);
        }
        // Russian roulette decides whether the path goes on beyond this segment.
        const double m = weight.max();
        if (m < kRoulette) {
            if (rng.uniform() * kRoulette >= m) break;
            weight = weight * (kRoulette / m);
        }
        // Then follow the path: a free flight with the smallest attenuation, per-channel weight
        // b exp(-c r) / (c_min exp(-c_min r)), and a new direction from the phase function.
        const double r = -std::log(1.0 - rng.uniform()) / m_c_min;
        X = X + d * r;
        if (length(X - start) > m_far) break;
        z_max = std::max(z_max, X.z);
        weight = weight * m_water.b * exp((m_water.c - Rgb(m_c_min)) * -r) * (1.0 / m_c_min);
        const PhaseSample ps = next_direction(X, d, rng);
        d = ps.direction;
        weight = weight * ps.weight;
    }
}

Estimate higher_orders_cumulative(const Transport& tr, const Vec3& dir,
                                  const std::vector<double>& t, const MonteCarlo& mc,
                                  std::uint64_t stream, const StopFlag* stop) {
    return higher_orders_cumulative(tr, Vec3(0.0, 0.0, 0.0), dir, t, mc, stream, stop);
}

Estimate higher_orders_cumulative(const Transport& tr, const Vec3& origin, const Vec3& dir,
                                  const std::vector<double>& t, const MonteCarlo& mc,
                                  std::uint64_t stream, const StopFlag* stop) {
    const std::size_t nk = t.size();
    Estimate out;
    out.value.assign(nk, Rgb());
    out.std_error.assign(nk, Rgb());
    if (nk == 0 || !(t.back() > 0.0) || mc.paths < 1) return out;
    Rng rng(mix_seed(mc.seed, stream));
    const Water& w = tr.water();
    // First scattering at path length s along the viewing ray, stratified, from a truncated
    // exponential (rate a) over [0, T]: most water light comes from near the camera.
    const double T = t.back();
    const double a = 0.5 * w.c.min();
    const double norm = a * T > 1e-9 ? -std::expm1(-a * T) : 0.0;
    // With a wall, sample k < nk - 1 holds the light whose path stayed at z <= Z[k].
    std::vector<double> Z(nk);
    for (std::size_t k = 0; k < nk; ++k) Z[k] = origin.z + dir.z * t[k];
    std::vector<Rgb> s1(nk), s2(nk), path(nk);
    const bool tail = mc.tail_above.max() > 0.0;
    if (tail) out.tail.assign(nk, Rgb());
    thread_local std::vector<std::pair<double, Rgb>> parts;
    // Path i from the generator's state before it: its light in `path` from sample k0 on, k0
    // returned (nk: it scattered beyond the last sample).
    const auto trace = [&](int i, Rng& g) {
        const double u = (i + g.uniform()) / mc.paths;
        double s, pdf;
        if (norm > 0.0) {
            s = -std::log1p(-u * norm) / a;
            pdf = a * std::exp(-a * s) / norm;
        } else {
            s = u * T;
            pdf = 1.0 / T;
        }
        const Vec3 X = origin + dir * s;
        const PhaseSample ps = tr.next_direction(X, dir, g);
        const Rgb f = w.b * exp(w.c * -s) * (ps.weight / pdf);
        parts.clear();
        tr.scattered_contributions(X, ps.direction, g, parts);
        const std::size_t k0 = std::size_t(std::lower_bound(t.begin(), t.end(), s) - t.begin());
        if (k0 >= nk) return nk;
        std::fill(path.begin() + std::ptrdiff_t(k0), path.end(), Rgb());
        for (const auto& [z, light] : parts) {
            std::size_t k = k0;
            if (mc.wall) {
                k = std::size_t(std::lower_bound(Z.begin(), Z.end(), z) - Z.begin());
                k = std::clamp(k, k0, nk - 1);
            }
            path[k] += f * light;
        }
        return k0;
    };
    // With a tail: each path's start and total, to split the bright ones once the mean is known.
    thread_local std::vector<Rng> starts;
    thread_local std::vector<Rgb> totals;
    // Filled path by path, not assigned whole: at the most paths they are hundreds of MB, whose
    // first touch would keep a stop waiting.
    if (tail) {
        starts.clear();
        totals.clear();
        starts.reserve(std::size_t(mc.paths));
        totals.reserve(std::size_t(mc.paths));
    }
    for (int i = 0; i < mc.paths; ++i) {
        throw_if_stopped(stop);
        if (tail) starts.push_back(rng);
        const std::size_t k0 = trace(i, rng);
        if (k0 >= nk) {
            if (tail) totals.push_back(Rgb());
            continue;
        }
        // This path's cumulative value at every sample from k0 on; its square for the errors.
        Rgb run;
        for (std::size_t k = k0; k < nk; ++k) {
            run += path[k];
            s1[k] += run;
            s2[k] += run * run;
        }
        if (tail) totals.push_back(run);
    }
    if (tail) {
        // The threshold per channel, then each path above it traced again (the same stream)
        // for its share above it at every sample.
        Rgb above = mc.tail_above;
        for (int c = 0; c < 3; ++c)
            above[c] = std::max(above[c], mc.tail_of_mean * s1[nk - 1][c] / mc.paths);
        for (int i = 0; i < mc.paths; ++i) {
            const Rgb& run = totals[std::size_t(i)];
            Rgb share;
            for (int c = 0; c < 3; ++c)
                if (run[c] > above[c]) share[c] = 1.0 - above[c] / run[c];
            if (!(share.max() > 0.0)) continue;
            Rng g = starts[std::size_t(i)];
            const std::size_t k0 = trace(i, g);
            Rgb sum;
            for (std::size_t k = k0; k < nk; ++k) {
                sum += path[k];
                out.tail[k] += sum * share;
            }
        }
    }
    const double n = mc.paths;
    for (Rgb& v : out.tail) v = v / n;
    for (std::size_t k = 0; k < nk; ++k) {
        out.value[k] = s1[k] / n;
        for (int c = 0; c < 3; ++c) {
            const double mean = s1[k][c] / n;
            out.std_error[k][c] = std::sqrt(std::max(0.0, s2[k][c] / n - mean * mean) / n);
        }
    }
    return out;
}

}  // namespace deepsea

#include "deepsea/optics/spherical_harmonics.h"

namespace deepsea {

ShEstimate scattered_radiance_sh(const Transport& tr, const Vec3& X, int samples, Rng& rng,
                                 const StopFlag* stop) {
    ShEstimate out;
    if (samples < 1) return out;
    double s2[27] = {};
    for (int i = 0; i < samples; ++i) {
        throw_if_stopped(stop);
        const PhaseSample ps = tr.any_direction(X, rng);
        const Rgb L = tr.scattered_radiance(X, ps.direction, rng) * ps.weight;
        double Y[kShCount];
        sh_basis(ps.direction.x, ps.direction.y, ps.direction.z, Y);
        for (int m = 0; m < kShCount; ++m) {
            for (int c = 0; c < 3; ++c) {
                const double f = L[c] * Y[m];
                out.value[3 * m + c] += f;
                s2[3 * m + c] += f * f;
            }
        }
    }
    const double n = samples;
    for (int i = 0; i < 27; ++i) {
        const double mean = out.value[i] / n;
        out.value[i] = mean;
        out.std_error[i] = std::sqrt(std::max(0.0, s2[i] / n - mean * mean) / n);
    }
    return out;
}

}  // namespace deepsea
