#include "deepsea/bake/bake.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/bake/accuracy.h"
#include "deepsea/bake/bake_ray.h"
#include "deepsea/bake/higher_orders.h"
#include "deepsea/bake/lattice_rule.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"

namespace deepsea {

namespace {

/// par for one stage of a bake: the stage's `done` is reported as offset + done of `total`,
/// so that the stages fill one progress bar.
/// A stage's items may weigh more than one column each (`weight`).
Parallel stage(const Parallel& par, long offset, long total, long weight = 1) {
    Parallel p = par;
    if (par.progress) {
        p.progress = [&par, offset, total, weight](long done, long) {
            return par.progress(offset + weight * done, total);
        };
    }
    return p;
}

/// A Monte Carlo column of the multiple-scattering stage costs about this many exact
/// single-scattering columns (measured on the demo's rig in Jerlov IB and 3C water).
constexpr long kMonteCarloColumnWeight = 32;

}  // namespace

void validate(const BakeSettings& s) {
    if (s.step < 0 || s.step > kMaxXyStep) {
        throw ConfigError("xy_step must be in [1, " + std::to_string(kMaxXyStep) +
                          "] pixels (or auto), got " + std::to_string(s.step));
    }
    if (s.depth_samples > kMaxDepthSamples) {
        throw ConfigError("depth_samples must be in [2, " + std::to_string(kMaxDepthSamples) +
                          "] (or auto), got " + std::to_string(s.depth_samples));
    }
    if (s.depth_samples != 0 && s.depth_samples < 2) {
        throw ConfigError("depth_samples must be >= 2 (or auto), got " +
                          std::to_string(s.depth_samples));
    }
    if (s.max_refinements < 0) throw ConfigError("max_refinements must be >= 0");
    if (s.strict && !s.check)
        throw ConfigError("a strict check needs the check: not with --no-check");
    if (s.z_max != 0.0 && !(s.z_max >= kMinZMax && s.z_max <= kMaxZMax)) {
        throw ConfigError("z_max must be in [" + short_number(kMinZMax) + ", " +
                          short_number(kMaxZMax) + "] metres (or auto), got " +
                          short_number(s.z_max));
    }
    if (!(s.tolerance > 0.0 && s.tolerance < 0.5)) {
        throw ConfigError("tolerance must be in (0, 0.5), got " + std::to_string(s.tolerance));
    }
    if (s.scattering == Scattering::Multiple &&
        (s.higher_orders.paths < 1 || s.higher_orders.stride < 0 ||
         s.higher_orders.lamp_samples < 1)) {
        throw ConfigError("multiple scattering: paths, stride and lamp samples must be >= 1");
    }
    // Checked whatever the scattering: a library's settings are validated once for all.
    if (s.higher_orders.paths > kMaxPaths) {
        throw ConfigError("paths must be in [1, " + std::to_string(kMaxPaths) +
                          "] (64 times the default), got " + std::to_string(s.higher_orders.paths));
    }
    if (s.higher_orders.lamp_samples > kMaxLampSamples) {
        throw ConfigError("lamp samples must be in [1, " + std::to_string(kMaxLampSamples) +
                          "] (64 times the default), got " +
                          std::to_string(s.higher_orders.lamp_samples));
    }
    if (s.scheme == DepthScheme::Log && !(s.z0 > 0.0)) {
        throw ConfigError("log depth scheme: z0 must be > 0 metres, got " + std::to_string(s.z0));
    }
    validate(s.quadrature);
}

double far_path_length(const Water& water, double tolerance) {
    const double c_min = water.c.min();
    if (!(c_min > 0.0)) return 1e4;
    return std::min(std::log(1e4 / tolerance) / (2.0 * c_min), 1e4);
}

double auto_z_max(const Camera& cam, const Rig& rig, const Water& water, int step, double tolerance,
                  const Quadrature& q, const Parallel& par, const std::optional<Port>& port) {
    const int ni = lattice_count(cam.width, step), nj = lattice_count(cam.height, step);
    const double t_far = far_path_length(water, tolerance);
    // Geometric path samples from 5 cm to t_far: the tail decays roughly exponentially, so a
    // constant ratio (about 12 % here) brackets the crossing equally well at any depth.
    constexpr int kM = 64;
    const double t_lo = std::min(0.05, 0.5 * t_far);
    std::vector<double> t(kM + 2);
    t[0] = 0.0;
    for (int m = 0; m <= kM; ++m) t[m + 1] = t_lo * std::pow(t_far / t_lo, double(m) / kM);

    // Each column's crossing in its own slot, the maximum taken afterwards: any thread count.
    std::vector<double> z_cross(std::size_t(ni) * nj, 0.0);
    parallel_for(
        z_cross.size(),
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t n = begin; n != end; ++n) {
                const BakeRay ray =
                    bake_ray(cam, port, double(n / nj) * step, double(n % nj) * step);
                const auto C =
                    backscatter_cumulative(rig, water, ray.origin, ray.dir, t, q, par.stop);
                const Rgb total = C.back();
                // Fraction of the total still to come beyond t[m], worst channel.
                const auto tail = [&](std::size_t m) {
                    double f = 0.0;
                    for (int c = 0; c < 3; ++c) {
                        if (total[c] > 0.0) f = std::max(f, (total[c] - C[m][c]) / total[c]);
                    }
                    return f;
                };
                std::size_t m = 0;
                while (m + 1 < t.size() && tail(m) > tolerance) ++m;
                double t_cross = t[m];
                if (m > 0 && tail(m) > 0.0) {
                    // log(tail) is convex in t, so the chord crosses the tolerance at or
                    // beyond the true crossing: conservative.
                    const double a = std::log(tail(m - 1)), b = std::log(tail(m));
                    const double w = (a - std::log(tolerance)) / (a - b);
                    t_cross = t[m - 1] + std::clamp(w, 0.0, 1.0) * (t[m] - t[m - 1]);
                }
                z_cross[n] = ray.depth(t_cross);
            }
        },
        par.or_grain(16));
    const double z_max = *std::max_element(z_cross.begin(), z_cross.end());
    // A ray with no light at all gives 0; a lattice must still have some depth.
    return std::clamp(std::ceil(z_max * 1000.0) / 1000.0, kMinZMax, kMaxZMax);
}

namespace {

/// The lattice and Monte Carlo spacing of one bake attempt: what the settings give, with the
/// automatic ones resolved.
struct Resolved {
    int step = 0, depth_samples = 0;
};

Resolved resolve(const Camera& cam, const Rig& rig, const BakeSettings& s) {
    Resolved r;
    r.step = s.step > 0 ? s.step : auto_step(cam, rig);
    r.depth_samples = s.depth_samples > 0 ? s.depth_samples : kDefaultDepthSamples;
    return r;
}

int mc_stride(const Camera& cam, const Rig& rig, const Water& water, const BakeSettings& s,
              int step) {
    return s.higher_orders.stride > 0
               ? s.higher_orders.stride
               : auto_ms_stride(cam, rig, water, step, s.higher_orders.paths);
}

/// Everything but the values: shared by bake() and bake_request() so their hashes agree.
BakeInfo make_info(const Camera& cam, const Rig& rig, const Water& water, const BakeSettings& s,
                   const Resolved& r, double z_max) {
    BakeInfo info;
    info.camera = cam;
    info.port = s.port;
    info.rig = rig;
    info.water = water;
    info.lattice = make_lattice(cam, r.step, s.scheme,
                                depth_samples(s.scheme, r.depth_samples, z_max, s.z0), s.z0);
    info.z_max_auto = s.z_max == 0.0;
    info.step_auto = s.step == 0;
    info.depth_samples_auto = s.depth_samples == 0;
    info.tolerance = info.z_max_auto ? s.tolerance : 0.0;
    info.quadrature = s.quadrature;
    info.scattering = s.scattering;
    if (s.scattering == Scattering::Multiple) {
        info.higher_orders = s.higher_orders;
        info.higher_orders.stride_auto = s.higher_orders.stride == 0;
        info.higher_orders.stride = mc_stride(cam, rig, water, s, r.step);
        info.higher_orders.wall = true;
        info.higher_orders.tail_above = kMsTailAbove;
        info.higher_orders.tail_of_mean = kMsTailOfMean;
        info.higher_orders.log_between = true;
        info.higher_orders.lamp_symmetric = true;
        info.higher_orders.roulette_after_next_event = true;
        info.higher_orders.tail_radius =
            ms_tail_radius(double(info.higher_orders.stride) * r.step / std::min(cam.fx, cam.fy),
                           ms_detail(cam, rig, water));
    }
    info.check.done = s.check;  // the request; bake() fills in what it measured
    info.baker_version = kBakerVersion;
    info.input_hash = input_hash(info);
    return info;
}

/// The exact single-scattering part of one attempt: z_max (searched if auto) and every
/// lattice column. `columns` and `total` place it on the progress bar.
Asset bake_single(const Camera& cam, const Rig& rig, const Water& water, const BakeSettings& s,
                  const Resolved& r, const Parallel& par, long total) {
    // before the z_max search, not after it
    check_lattice_size(lattice_count(cam.width, r.step), lattice_count(cam.height, r.step),
                       r.depth_samples + 1);
    const bool automatic = s.z_max == 0.0;
    const long columns = long(lattice_count(cam.width, r.step)) * lattice_count(cam.height, r.step);
    const double z_max = automatic ? auto_z_max(cam, rig, water, r.step, s.tolerance, s.quadrature,
                                                stage(par, 0, total), s.port)
                                   : s.z_max;
    Asset asset;
    asset.info = make_info(cam, rig, water, s, r, z_max);
    check_storable(cam, asset.info.lattice);  // before the columns, not at writing
    asset.allocate();
    const Lattice& l = asset.info.lattice;
    // Column n = i * nj + j owns values[n * nk * 3 ...]: fixed slots, any thread count.
    parallel_for(
        std::size_t(l.columns()),
        [&](std::size_t begin, std::size_t end) {
            std::vector<double> t(l.z.size());
            for (std::size_t n = begin; n != end; ++n) {
                const int i = int(n / l.nj), j = int(n % l.nj);
                // Pinhole: t = z / cos(phi) = z |r|; through a port, the water-side ray's path
                // from the outer surface to planar depth z (0 inside the housing).
                const BakeRay ray = bake_ray(cam, s.port, l.u(i), l.v(j));
                for (std::size_t k = 0; k < t.size(); ++k) t[k] = ray.path(l.z[k]);
                const auto C = backscatter_cumulative(rig, water, ray.origin, ray.dir, t,
                                                      s.quadrature, par.stop);
                float* out = asset.values.data() + asset.index(i, j, 0);
                for (std::size_t k = 0; k < C.size(); ++k) {
                    out[3 * k] = float(C[k].r);
                    out[3 * k + 1] = float(C[k].g);
                    out[3 * k + 2] = float(C[k].b);
                }
            }
        },
        stage(par, automatic ? columns : 0, total).or_grain(16));
    return asset;
}

std::string percent(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g %%", 100.0 * x);
    return buf;
}

}  // namespace

BakeInfo bake_request(const Camera& cam, const Rig& rig, const Water& water,
                      const BakeSettings& s) {
    validate(s);
    return make_info(cam, rig, water, s, resolve(cam, rig, s), s.z_max == 0.0 ? 1.0 : s.z_max);
}

Asset bake(const Camera& cam, const Rig& rig, const Water& water, const BakeSettings& s,
           const Parallel& par) {
    validate(s);
    if (rig.lights.empty())
        throw ConfigError("rig '" + rig.name + "' has no lights: nothing to bake");
    if (s.port) {  // before any work: every column's ray must reach the water
        validate(*s.port);
        check_port_view(*s.port, cam);
    }
    Resolved r = resolve(cam, rig, s);
    Asset asset;
    for (int attempt = 0;; ++attempt) {
        // The bar: the auto z_max search visits the same columns as the bake (first half), then
        // the Monte Carlo columns, weighted by their cost.
        const int ni = lattice_count(cam.width, r.step), nj = lattice_count(cam.height, r.step);
        const long columns = long(ni) * nj;
        const long mc_weight =
            s.scattering == Scattering::Multiple
                ? kMonteCarloColumnWeight *
                      higher_order_columns(ni, nj, mc_stride(cam, rig, water, s, r.step))
                : 0;
        const long total = (s.z_max == 0.0 ? 2 * columns : columns) + mc_weight;
        asset = bake_single(cam, rig, water, s, r, par, total);
        if (!s.check) break;
        // The check is not on the bar (it keeps its progress strictly increasing and counting
        // columns): a few hundred test pixels, under a second; a cancel waits for it.
        LatticeCheck check = check_lattice(asset, Parallel{par.threads}.with_stop(par.stop));
        check.refinements = attempt;
        asset.info.check = check;
        if (meets_bar(check) || attempt == s.max_refinements) break;
        const Refinement next =
            refine(check, r.step, r.depth_samples, s.step == 0, s.depth_samples == 0);
        if (!next.changed()) break;
        if (next.step > 0) r.step = next.step;
        if (next.depth_samples > 0) r.depth_samples = next.depth_samples;
    }
    const LatticeCheck& check = asset.info.check;
    if (s.strict && !meets_bar(check)) {
        throw AccuracyError("bake check: the lattice (step " +
                            std::to_string(asset.info.lattice.step) + " px, K " +
                            std::to_string(asset.info.lattice.slabs()) + ") misses the bar: mean " +
                            percent(check.mean_rel) + ", max " + percent(check.max_rel) + " (bar " +
                            percent(kBarMeanRel) + " / " + percent(kBarMaxRel) +
                            "); give a finer xy_step or depth_samples");
    }
    if (s.scattering == Scattering::Multiple) {
        const Lattice& l = asset.info.lattice;
        const long columns = long(l.ni) * l.nj;
        const long mc_weight = kMonteCarloColumnWeight *
                               higher_order_columns(l.ni, l.nj, asset.info.higher_orders.stride);
        const long total = (s.z_max == 0.0 ? 2 * columns : columns) + mc_weight;
        add_higher_orders(asset, stage(par, total - mc_weight, total, kMonteCarloColumnWeight));
        add_lamp_fields(asset, Parallel{par.threads}.with_stop(par.stop));
        add_forward_psf(asset, Parallel{par.threads}.with_stop(par.stop));
    }
    return asset;
}

}  // namespace deepsea
