#include "deepsea/optics/forward_transport.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "deepsea/core/error.h"
#include "deepsea/core/random.h"
#include "deepsea/optics/phase_sampling.h"

namespace deepsea {

namespace {

/// Below this largest channel weight Russian roulette decides (as multiple_scattering.cpp).
constexpr double kRoulette = 0.1;
constexpr int kBlock = 2048;  ///< paths per block: blocks are summed in order, any threads

/// One block's sums: shares per depth and ring, and per depth the sum of squares of each
/// path's score (a path scores a depth at most once).
struct Sums {
    std::vector<Rgb> share, s1, s2;
};

}  // namespace

Rgb ForwardPsfTable::total(int k) const {
    Rgb t;
    for (int i = 0; i < rings(); ++i) t += share[std::size_t(k) * rings() + i];
    return t;
}

void ForwardPsfTable::validate(const char* what) const {
    const std::string w(what);
    const auto bad = [&](const std::string& why) { throw ConfigError(w + ": " + why); };
    if (depth.empty()) bad("no depths");
    if (ring_edge.size() < 2) bad("fewer than two ring edges");
    if (share.size() != depth.size() * std::size_t(rings()))
        bad("share holds " + std::to_string(share.size()) +
            " values, not depths x rings = " + std::to_string(depth.size() * std::size_t(rings())));
    if (direct.size() != depth.size() || std_error.size() != depth.size())
        bad("direct and std_error need one value per depth");
    for (std::size_t k = 0; k < depth.size(); ++k) {
        if (!(depth[k] > 0.0) || !std::isfinite(depth[k]) || (k > 0 && !(depth[k] > depth[k - 1])))
            bad("depths must be finite, > 0 and ascending");
    }
    if (ring_edge.front() != 0.0 || std::abs(ring_edge.back() - M_PI / 2) > 1e-9)
        bad("ring edges must run from 0 to pi/2");
    for (std::size_t i = 1; i < ring_edge.size(); ++i)
        if (!(ring_edge[i] > ring_edge[i - 1])) bad("ring edges must ascend");
    const auto ok = [](const Rgb& v) {
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(v[c]) || v[c] < 0.0) return false;
        return true;
    };
    for (const Rgb& v : share)
        if (!ok(v)) bad("a share is negative or not finite");
    for (std::size_t k = 0; k < depth.size(); ++k)
        if (!ok(direct[k]) || !ok(std_error[k])) bad("a direct or std_error value is bad");
}

std::vector<double> forward_psf_depths(double far, int n) {
    if (!(far > 0.0) || !std::isfinite(far) || n < 1)
        throw ConfigError("forward_psf_depths: needs a finite far > 0 and n >= 1");
    std::vector<double> d(n);
    for (int k = 0; k < n; ++k) d[k] = far * std::pow(double(k + 1) / n, 2.0);
    return d;
}

ForwardPsfTable trace_forward_psf(const Water& water, const std::vector<double>& depths,
                                  const ForwardTransportSettings& settings, const Parallel& par) {
    if (settings.paths < 1) throw ConfigError("forward scatter table: paths must be >= 1");
    if (settings.max_order < 1) throw ConfigError("forward scatter table: max_order must be >= 1");
    if (settings.rings < 2) throw ConfigError("forward scatter table: rings must be >= 2");
    ForwardPsfTable t;
    t.depth = depths;
    t.paths = settings.paths;
    t.seed = settings.seed;
    const int R = settings.rings;
    t.ring_edge.resize(R + 1);
    t.ring_edge[0] = 0.0;
    for (int i = 1; i <= R; ++i)
        t.ring_edge[i] = 1e-4 * std::pow(M_PI / 2 / 1e-4, double(i - 1) / (R - 1));
    t.ring_edge[R] = M_PI / 2;
    const int K = int(depths.size());
    t.direct.resize(K);
    for (int k = 0; k < K; ++k) t.direct[k] = exp(water.c * -depths[k]);
    t.share.assign(std::size_t(K) * R, Rgb());
    t.std_error.assign(K, Rgb());
    if (K == 0) throw ConfigError("forward scatter table: no depths");
    for (int k = 0; k < K; ++k) {
        if (!(depths[k] > 0.0) || (k > 0 && !(depths[k] > depths[k - 1])))
            throw ConfigError("forward scatter table: depths must be > 0 and ascending");
    }
    if (water.b.max() <= 0.0) return t;  // nothing scatters: the direct part is all

    const PhaseSampler sampler(water.phase);
    const double s = std::max(water.c.min(), 1e-9);  // free flights' sampling rate
    const Rgb excess = water.c - Rgb(s);
    const double D = depths.back();
    const double norm = -std::expm1(-s * D);  // share of first flights ending inside D
    const int n = settings.paths;
    const int blocks = (n + kBlock - 1) / kBlock;
    std::vector<Sums> sums(blocks);

    parallel_for(
        std::size_t(blocks),
        [&](std::size_t b0, std::size_t b1) {
            for (std::size_t blk = b0; blk < b1; ++blk) {
                throw_if_stopped(par.stop);
                Sums& S = sums[blk];
                S.share.assign(std::size_t(K) * R, Rgb());
                S.s1.assign(K, Rgb());
                S.s2.assign(K, Rgb());
                const int i0 = int(blk) * kBlock, i1 = std::min(n, i0 + kBlock);
                for (int i = i0; i < i1; ++i) {
                    Rng rng(mix_seed(settings.seed, std::uint64_t(i)));
                    // First scattering on [0, D], stratified, truncated exponential at rate s.
                    const double u = (i + rng.uniform()) / n;
                    const double t1 = -std::log1p(-u * norm) / s;
                    Rgb w = water.b * exp(excess * -t1) * (norm / s);
                    int next =
                        int(std::upper_bound(depths.begin(), depths.end(), t1) - depths.begin());
                    Vec3 X(0.0, 0.0, t1), d(0.0, 0.0, 1.0);
                    for (int order = 1; order <= settings.max_order && next < K; ++order) {
                        const PhaseSample ps = sampler.sample(d, rng.uniform(), rng.uniform());
                        d = ps.direction;
                        w = w * ps.weight;
                        const double r = -std::log(1.0 - rng.uniform()) / s;
                        // Score every plane this flight crosses first (moving deeper).
                        while (next < K && d.z > 0.0 && X.z + r * d.z >= depths[next]) {
                            const double h = (depths[next] - X.z) / d.z;
                            const Vec3 P = X + d * h;
                            const Rgb f = w * exp(excess * -h);
                            const double psi = std::atan2(std::hypot(P.x, P.y), P.z);
                            const int ring = std::clamp(
                                int(std::upper_bound(t.ring_edge.begin(), t.ring_edge.end(), psi) -
                                    t.ring_edge.begin()) -
                                    1,
                                0, R - 1);
                            S.share[std::size_t(next) * R + ring] += f;
                            S.s1[next] += f;
                            S.s2[next] += f * f;
                            ++next;
                        }
                        if (next >= K || order == settings.max_order) break;
                        X = X + d * r;
                        w = w * water.b * exp(excess * -r) * (1.0 / s);
                        const double m = w.max();
                        if (m < kRoulette) {
                            if (rng.uniform() * kRoulette >= m) break;
                            w = w * (kRoulette / m);
                        }
                    }
                }
            }
        },
        par.or_grain(1));

    std::vector<Rgb> s1(K), s2(K);
    for (const Sums& S : sums) {
        for (std::size_t j = 0; j < t.share.size(); ++j) t.share[j] += S.share[j];
        for (int k = 0; k < K; ++k) {
            s1[k] += S.s1[k];
            s2[k] += S.s2[k];
        }
    }
    for (Rgb& v : t.share) v = v / double(n);
    for (int k = 0; k < K; ++k) {
        for (int c = 0; c < 3; ++c) {
            const double mean = s1[k][c] / n;
            t.std_error[k][c] = std::sqrt(std::max(0.0, s2[k][c] / n - mean * mean) / n);
        }
    }
    return t;
}

}  // namespace deepsea
