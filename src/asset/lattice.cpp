#include "deepsea/asset/lattice.h"

#include <algorithm>
#include <cmath>

#include "deepsea/core/error.h"

namespace deepsea {

namespace {

struct SchemeName {
    DepthScheme scheme;
    const char* name;
};

constexpr SchemeName kSchemes[] = {
    {DepthScheme::Uniform, "uniform"},
    {DepthScheme::Taylor, "taylor"},
    {DepthScheme::Sqrt, "sqrt"},
    {DepthScheme::Log, "log"},
};

/// Slab n of the Taylor scheme is proportional to K^n / n!, the n-th term of the series of
/// e^K (docs/asset-format.md). Summed in logs: K^n overflows a double for K > 150.
std::vector<double> taylor_samples(int K, double z_max) {
    std::vector<double> term(K);
    double log_max = -1e300;
    for (int n = 0; n < K; ++n) {
        term[n] = n * std::log(double(K)) - std::lgamma(n + 1.0);
        log_max = std::max(log_max, term[n]);
    }
    std::vector<double> z(K + 1, 0.0);
    double sum = 0.0;
    for (int n = 0; n < K; ++n) {
        sum += std::exp(term[n] - log_max);
        z[n + 1] = sum;
    }
    for (double& x : z) x = z_max * (x / sum);
    return z;
}

}  // namespace

const char* to_string(DepthScheme scheme) {
    for (const auto& s : kSchemes) {
        if (s.scheme == scheme) return s.name;
    }
    return "unknown";
}

DepthScheme parse_depth_scheme(const std::string& name) {
    for (const auto& s : kSchemes) {
        if (name == s.name) return s.scheme;
    }
    throw ConfigError("unknown depth scheme '" + name + "' (known: uniform, taylor, sqrt, log)");
}

std::vector<double> depth_samples(DepthScheme scheme, int K, double z_max, double z0) {
    if (K < 1)
        throw ConfigError("depth samples: need at least one slab, got K = " + std::to_string(K));
    if (!(z_max > 0.0) || !std::isfinite(z_max)) {
        throw ConfigError("depth samples: z_max must be > 0 metres, got " + std::to_string(z_max));
    }
    if (scheme == DepthScheme::Log && !(z0 > 0.0)) {
        throw ConfigError("depth samples: log scheme needs z0 > 0, got " + std::to_string(z0));
    }
    if (scheme == DepthScheme::Taylor) return taylor_samples(K, z_max);
    std::vector<double> z(K + 1);
    for (int k = 0; k <= K; ++k) {
        const double x = double(k) / K;
        switch (scheme) {
            case DepthScheme::Uniform:
                z[k] = z_max * x;
                break;
            case DepthScheme::Sqrt:
                z[k] = z_max * x * x;
                break;
            case DepthScheme::Log:
                z[k] = z0 * std::expm1(x * std::log1p(z_max / z0));
                break;
            case DepthScheme::Taylor:
                break;
        }
    }
    z[0] = 0.0;
    z[K] = z_max;  // exact, whatever the rounding of the formula
    return z;
}

int lattice_count(int pixels, int step) {
    if (pixels <= 1) return 1;
    return (pixels - 1 + step - 1) / step + 1;
}

DepthPosition Lattice::depth_position(double zz) const {
    const int K = slabs();
    if (!(zz > 0.0)) {
        // NaN means open water like +inf; only a real z <= 0 is the camera centre.
        if (!std::isnan(zz)) return {0, 0.0};
        return {K - 1, 1.0};
    }
    if (zz >= z.back()) return {K - 1, 1.0};
    // A first guess from the scheme's inverse, then a fix-up against the stored samples, which
    // are the truth (a file's samples went through a text round trip).
    double x = 0.0;
    switch (scheme) {
        case DepthScheme::Uniform:
            x = zz / z.back();
            break;
        case DepthScheme::Sqrt:
            x = std::sqrt(zz / z.back());
            break;
        case DepthScheme::Log:
            x = std::log1p(zz / z0) / std::log1p(z.back() / z0);
            break;
        case DepthScheme::Taylor: {
            const auto it = std::upper_bound(z.begin(), z.end(), zz);
            x = double(it - z.begin() - 1) / K;
            break;
        }
    }
    int k = std::clamp(int(x * K), 0, K - 1);
    while (k > 0 && z[k] > zz) --k;
    while (k < K - 1 && z[k + 1] <= zz) ++k;
    const double h = z[k + 1] - z[k];
    const double w = h > 0.0 ? (zz - z[k]) / h : 0.0;
    return {k, std::clamp(w, 0.0, 1.0)};
}

bool Lattice::operator==(const Lattice& o) const {
    return step == o.step && ni == o.ni && nj == o.nj && scheme == o.scheme &&
           (scheme != DepthScheme::Log || z0 == o.z0) && z == o.z;
}

void check_lattice_size(long long ni, long long nj, long long nk) {
    const long double points = (long double)ni * nj * nk;
    if (points > kMaxLatticePoints) {
        throw ConfigError("lattice of " + std::to_string(ni) + " x " + std::to_string(nj) +
                          " columns x " + std::to_string(nk) + " depth samples is larger than " +
                          "the limit of " + std::to_string(kMaxLatticePoints / 1000000) +
                          " million points (use a larger xy step or fewer depth samples)");
    }
}

Lattice make_lattice(const Camera& camera, int step, DepthScheme scheme,
                     std::vector<double> z_samples, double z0) {
    if (step < 1) throw ConfigError("xy step must be >= 1 pixel, got " + std::to_string(step));
    if (camera.width < 1 || camera.height < 1) {
        throw ConfigError("camera has no pixels (" + std::to_string(camera.width) + "x" +
                          std::to_string(camera.height) + ")");
    }
    if (z_samples.size() < 2) throw ConfigError("a lattice needs at least 2 depth samples");
    if (z_samples.front() != 0.0) throw ConfigError("the first depth sample must be 0");
    for (std::size_t k = 1; k < z_samples.size(); ++k) {
        if (!(z_samples[k] > z_samples[k - 1]) || !std::isfinite(z_samples[k])) {
            throw ConfigError("depth samples must ascend strictly (sample " + std::to_string(k) +
                              ")");
        }
    }
    check_lattice_size(lattice_count(camera.width, step), lattice_count(camera.height, step),
                       (long long)z_samples.size());
    Lattice l;
    l.step = step;
    l.ni = lattice_count(camera.width, step);
    l.nj = lattice_count(camera.height, step);
    l.scheme = scheme;
    l.z0 = z0;
    l.z = std::move(z_samples);
    return l;
}

}  // namespace deepsea
