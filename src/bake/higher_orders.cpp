#include "deepsea/bake/higher_orders.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "deepsea/bake/bake_ray.h"
#include "deepsea/bake/higher_orders_check.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/forward_transport.h"
#include "deepsea/optics/multiple_scattering.h"

namespace deepsea {

int ms_tail_radius(double spacing, double detail) {
    if (!(spacing > 0.0) || !(detail > 0.0)) return 0;
    return int(std::min(double(kMsTailRadius), std::floor(kMsTailPerDetail * detail / spacing)));
}

long higher_order_columns(int ni, int nj, int stride) {
    return long(computed_indices(ni, stride).size()) * long(computed_indices(nj, stride).size());
}

namespace {

/// Farthest a lit surface of this asset can be from lamp L: the frustum's corners at z_max.
double reach(const Camera& cam, double z_max, const Light& L) {
    double r = 0.0;
    for (double u : {-0.5, cam.width - 0.5})
        for (double v : {-0.5, cam.height - 0.5})
            r = std::max(r, length(cam.ray(u, v) * z_max - L.position));
    return r;
}

/// Replaces each computed column's tail (the paths' light above its threshold, part of its
/// value) with the tent-weighted mean of the tails of the columns within `radius` computed
/// columns of it: the rare bright paths that any of them could have drawn, shared among them.
/// The sum over columns of equal weight stays what it was on average; the column's own body
/// (below the threshold) is kept.
void pool_tails(MsColumns& ms, const std::vector<Rgb>& tails, int radius) {
    const long A = long(ms.ci.size()), B = long(ms.cj.size());
    const std::size_t nk = ms.nk;
    std::vector<Rgb> pooled(nk);
    std::vector<Rgb> out = ms.values;
    for (long a = 0; a < A; ++a) {
        for (long b = 0; b < B; ++b) {
            std::fill(pooled.begin(), pooled.end(), Rgb());
            double weights = 0.0;
            for (long p = std::max(0L, a - radius); p <= std::min(A - 1, a + radius); ++p) {
                for (long q = std::max(0L, b - radius); q <= std::min(B - 1, b + radius); ++q) {
                    const double w = double(radius + 1 - std::labs(p - a)) *
                                     double(radius + 1 - std::labs(q - b));
                    const Rgb* t = tails.data() + (p * B + q) * long(nk);
                    for (std::size_t k = 0; k < nk; ++k) pooled[k] += t[k] * w;
                    weights += w;
                }
            }
            const std::size_t n = std::size_t(a * B + b) * nk;
            for (std::size_t k = 0; k < nk; ++k)
                out[n + k] = ms.values[n + k] - tails[n + k] + pooled[k] * (1.0 / weights);
        }
    }
    ms.values = std::move(out);
}

bool same_profile(const Rid& a, const Rid& b) {
    return a.kind == b.kind && a.sigma_deg == b.sigma_deg && a.angle_deg == b.angle_deg &&
           a.value == b.value && a.cutoff_deg == b.cutoff_deg;
}

}  // namespace

void add_lamp_fields(Asset& asset, const Parallel& par) {
    const BakeInfo& info = asset.info;
    const std::vector<Light>& lights = info.rig.lights;
    LampFieldSettings ls;
    ls.samples = info.higher_orders.lamp_samples;
    ls.seed = info.higher_orders.seed;
    ls.symmetric = info.higher_orders.lamp_symmetric;
    for (const Light& L : lights)
        ls.r_max = std::max(ls.r_max, 1.1 * reach(info.camera, info.lattice.z_max(), L));
    ls.r_max = std::max(ls.r_max, 10.0 * ls.r0);
    asset.lamp_fields.assign(lights.size(), LampField{});
    HigherOrderSettings& h = asset.info.higher_orders;
    h.lamp_rel_std_error = 0.0;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        std::size_t twin = 0;
        while (twin < l && !same_profile(lights[twin].rid, lights[l].rid)) ++twin;
        asset.lamp_fields[l] =
            twin < l ? asset.lamp_fields[twin] : bake_lamp_field(lights[l], info.water, ls, par);
        h.lamp_rel_std_error += asset.lamp_fields[l].rel_std_error / double(lights.size());
    }
}

void add_higher_orders(Asset& asset, const Parallel& par) {
    HigherOrderSettings& s = asset.info.higher_orders;
    if (s.paths < 1)
        throw ConfigError("multiple scattering: paths must be >= 1, got " +
                          std::to_string(s.paths));
    if (s.stride < 1)
        throw ConfigError("multiple scattering: stride must be >= 1, got " +
                          std::to_string(s.stride));
    const BakeInfo& info = asset.info;
    const Lattice& l = info.lattice;
    const Transport transport(info.rig, info.water);
    MsColumns ms;
    ms.log = s.log_between;
    ms.ci = computed_indices(l.ni, s.stride);
    ms.cj = computed_indices(l.nj, s.stride);
    const std::vector<int>&ci = ms.ci, &cj = ms.cj;
    const std::size_t nk = ms.nk = std::size_t(l.nk());
    std::vector<Rgb>& coarse = ms.values;
    coarse.resize(ci.size() * cj.size() * nk);
    std::vector<double> rel_error(ci.size() * cj.size()), fraction(ci.size() * cj.size());
    std::vector<Rgb> tails(coarse.size());  // the paths' light above each column's threshold
    parallel_for(
        ci.size() * cj.size(),
        [&](std::size_t begin, std::size_t end) {
            std::vector<double> t(nk);
            for (std::size_t n = begin; n < end; ++n) {
                const int i = ci[n / cj.size()], j = cj[n % cj.size()];
                // the column's ray: pinhole, or the water-side ray through the port
                const BakeRay ray = bake_ray(info.camera, info.port, l.u(i), l.v(j));
                for (std::size_t k = 0; k < nk; ++k) t[k] = ray.path(l.z[k]);
                const std::uint64_t stream =
                    std::uint64_t(i) * std::uint64_t(l.nj) + std::uint64_t(j);
                const Rgb single = asset.at(i, j, int(nk) - 1);
                MonteCarlo mc{s.paths, s.seed, s.wall};
                mc.tail_of_mean = s.tail_of_mean;
                if (s.tail_above > 0.0)
                    for (int c = 0; c < 3; ++c)
                        mc.tail_above[c] =
                            std::max(s.tail_above * single[c], std::numeric_limits<double>::min());
                const Estimate e = higher_orders_cumulative(transport, ray.origin, ray.dir, t, mc,
                                                            stream, par.stop);
                std::copy(e.value.begin(), e.value.end(), coarse.begin() + std::ptrdiff_t(n * nk));
                if (!e.tail.empty())
                    std::copy(e.tail.begin(), e.tail.end(), tails.begin() + std::ptrdiff_t(n * nk));
                double err = 0.0, frac = 0.0;
                for (int c = 0; c < 3; ++c) {
                    const double total = single[c] + e.value.back()[c];
                    if (total > 0.0) {
                        err += e.std_error.back()[c] / total / 3.0;
                        frac += e.value.back()[c] / total / 3.0;
                    }
                }
                rel_error[n] = err;
                fraction[n] = frac;
            }
        },
        Parallel{par.threads, 1, par.progress}.with_stop(par.stop));
    if (s.tail_above > 0.0) pool_tails(ms, tails, s.tail_radius);
    // The check needs the single scattering alone, so it runs before the sum.
    s.check = info.check.done
                  ? check_higher_orders(asset, ms, Parallel{par.threads}.with_stop(par.stop))
                  : HigherOrderCheck{};
    s.spacing_rad = double(s.stride) * l.step / std::min(info.camera.fx, info.camera.fy);

    for (int i = 0; i < l.ni; ++i) {
        for (int j = 0; j < l.nj; ++j) {
            float* out = asset.values.data() + asset.index(i, j, 0);
            for (std::size_t k = 0; k < nk; ++k) {
                const Rgb v = ms.at(i, j, k);
                for (int c = 0; c < 3; ++c) out[3 * k + c] += float(v[c]);
            }
        }
    }
    s.rel_std_error = s.fraction = 0.0;
    for (std::size_t n = 0; n < rel_error.size(); ++n) {
        s.rel_std_error += rel_error[n] / double(rel_error.size());
        s.fraction += fraction[n] / double(fraction.size());
    }
    asset.info.scattering = Scattering::Multiple;
}

void add_forward_psf(Asset& asset, const Parallel& par) {
    const Water& water = asset.info.water;
    if (!water.forward.enabled || water.forward.model != ForwardModel::PhaseFunction) return;
    const Camera& cam = asset.info.camera;
    double corner = 0.0;
    for (const double u : {0.0, double(cam.width - 1)}) {
        for (const double v : {0.0, double(cam.height - 1)})
            corner = std::max(corner, length(cam.ray(u, v)));
    }
    ForwardTransportSettings fs;
    fs.seed = asset.info.higher_orders.seed;
    asset.forward_psf =
        trace_forward_psf(water, forward_psf_depths(asset.info.lattice.z_max() * corner), fs, par);
}

}  // namespace deepsea
