#include "deepsea/bake/accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deepsea/bake/bake.h"
#include "deepsea/bake/bake_ray.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"

namespace deepsea {

namespace {

std::vector<int> test_coords(int n, int stride) {
    std::vector<int> out;
    for (int x = stride / 2; x < n; x += stride) out.push_back(x);
    if (out.empty() || out.back() != n - 1) out.push_back(n - 1);
    return out;
}

double rel_error(const Rgb& lookup, const Rgb& exact) {
    double e = 0.0;
    for (int c = 0; c < 3; ++c) {
        if (exact[c] > 0.0) {
            e = std::max(e, std::abs(lookup[c] - exact[c]) / exact[c]);
        } else if (lookup[c] != 0.0) {
            e = std::max(e, 1.0);  // light where there is none: count as 100 %
        }
    }
    return e;
}

std::string plane_name(double z) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "plane %g m", z);
    return buf;
}

}  // namespace

std::vector<AccuracyRow> evaluate_asset_accuracy(const Asset& asset, const AccuracyOptions& opt,
                                                 const Parallel& par) {
    if (opt.stride < 1) throw ConfigError("accuracy stride must be >= 1");
    const BakeInfo& info = asset.info;
    const Camera& cam = info.camera;
    const double z_max = info.lattice.z_max();

    // Scenes: each plane depth, then open water (the lookup at z_max) against the integral to
    // z_max and to the far path length.
    std::vector<AccuracyRow> rows;
    std::vector<double> exact_z;  // planar depth of the exact integral per row
    for (double z : opt.plane_depths) {
        if (!(z > 0.0)) throw ConfigError("accuracy plane depths must be > 0");
        rows.push_back({plane_name(z), z});
        exact_z.push_back(z);
    }
    const double t_far = far_path_length(info.water, info.z_max_auto ? info.tolerance : 1e-4);
    if (opt.open_water) {
        rows.push_back({"open water (z_max)", z_max});
        exact_z.push_back(z_max);
        rows.push_back({"open water (inf)", z_max});
        exact_z.push_back(-1.0);  // to t_far along the ray
    }
    const std::size_t R = rows.size();

    const std::vector<int> us = opt.us.empty() ? test_coords(cam.width, opt.stride) : opt.us;
    const std::vector<int> vs = opt.vs.empty() ? test_coords(cam.height, opt.stride) : opt.vs;
    // Per test pixel and row: the error; reduced in a fixed order afterwards.
    std::vector<double> err(us.size() * vs.size() * R, 0.0);

    parallel_for(
        vs.size(),
        [&](std::size_t jv0, std::size_t jv1) {
            std::vector<double> t;
            std::vector<std::size_t> order(R);
            for (std::size_t jv = jv0; jv != jv1; ++jv) {
                for (std::size_t iu = 0; iu < us.size(); ++iu) {
                    const double u = us[iu], v = vs[jv];
                    // The pixel's own ray: pinhole, or its water-side ray through the port.
                    const BakeRay ray = bake_ray(cam, info.port, u, v);
                    // One cumulative integral per pixel serves every scene: sort the path lengths.
                    for (std::size_t r = 0; r < R; ++r) order[r] = r;
                    const auto path = [&](std::size_t r) {
                        return exact_z[r] < 0.0 ? std::max(t_far, ray.path(z_max))
                                                : ray.path(exact_z[r]);
                    };
                    std::sort(order.begin(), order.end(),
                              [&](std::size_t a, std::size_t b) { return path(a) < path(b); });
                    t.assign(1, 0.0);
                    for (std::size_t r : order) t.push_back(path(r));
                    const auto C = backscatter_cumulative(info.rig, info.water, ray.origin, ray.dir,
                                                          t, opt.quadrature, par.stop);
                    for (std::size_t n = 0; n < R; ++n) {
                        const std::size_t r = order[n];
                        const Rgb lookup = asset.sample(u, v, rows[r].z);
                        err[(jv * us.size() + iu) * R + r] = rel_error(lookup, C[n + 1]);
                    }
                }
            }
        },
        par.or_grain(1));

    for (std::size_t r = 0; r < R; ++r) {
        double sum = 0.0;
        AccuracyRow& row = rows[r];
        for (std::size_t jv = 0; jv < vs.size(); ++jv) {
            for (std::size_t iu = 0; iu < us.size(); ++iu) {
                const double e = err[(jv * us.size() + iu) * R + r];
                sum += e;
                if (e > row.max_rel) {
                    row.max_rel = e;
                    row.max_u = us[iu];
                    row.max_v = vs[jv];
                }
            }
        }
        row.pixels = long(us.size() * vs.size());
        row.mean_rel = sum / double(row.pixels);
    }
    return rows;
}

namespace {

/// Every m-th of n lattice nodes (pixel i * step), or the centre of every m-th cell between
/// them (i * step + step / 2), within the image of `pixels` pixels.
std::vector<int> lattice_coords(int n, int step, int m, bool centres, int pixels) {
    std::vector<int> out;
    for (int i = 0; i < (centres ? n - 1 : n); i += m) {
        const int x = i * step + (centres ? step / 2 : 0);
        if (x < pixels) out.push_back(x);
    }
    if (out.empty()) out.push_back(0);
    return out;
}

}  // namespace

LatticeCheck check_lattice(const Asset& asset, const Parallel& par) {
    const Lattice& l = asset.lattice();
    const Camera& cam = asset.info.camera;
    const long cells = long(std::max(1, l.ni - 1)) * std::max(1, l.nj - 1);
    const int m = std::max(1, int(std::floor(std::sqrt(double(cells) / kCheckCells))));
    AccuracyOptions opt;
    // The bake's own integrator at <= 1e-6: 1e-4 of the bar, so the reference is not what errs.
    opt.quadrature = asset.info.quadrature;
    opt.quadrature.rel_tol = std::min(opt.quadrature.rel_tol, 1e-6);
    const auto worst = [](const std::vector<AccuracyRow>& rows, double& mean, double& max, int* u,
                          int* v) {
        for (const AccuracyRow& r : rows) {
            mean = std::max(mean, r.mean_rel);
            if (r.max_rel > max) {
                max = r.max_rel;
                if (u) *u = r.max_u, *v = r.max_v;
            }
        }
    };
    LatticeCheck check;
    check.done = true;
    // Cell centres: xy and depth interpolation together.
    opt.us = lattice_coords(l.ni, l.step, m, true, cam.width);
    opt.vs = lattice_coords(l.nj, l.step, m, true, cam.height);
    const auto centre_rows = evaluate_asset_accuracy(asset, opt, par);
    // Lattice columns: depth interpolation alone.
    opt.us = lattice_coords(l.ni, l.step, 2 * m, false, cam.width);
    opt.vs = lattice_coords(l.nj, l.step, 2 * m, false, cam.height);
    const auto column_rows = evaluate_asset_accuracy(asset, opt, par);
    worst(column_rows, check.columns_mean_rel, check.columns_max_rel, nullptr, nullptr);
    worst(centre_rows, check.mean_rel, check.max_rel, &check.max_u, &check.max_v);
    check.mean_rel = std::max(check.mean_rel, check.columns_mean_rel);
    if (check.columns_max_rel > check.max_rel) {
        check.max_rel = check.columns_max_rel;
        for (const AccuracyRow& r : column_rows) {
            if (r.max_rel == check.max_rel) check.max_u = r.max_u, check.max_v = r.max_v;
        }
    }
    check.pixels = centre_rows.front().pixels + column_rows.front().pixels;
    return check;
}

}  // namespace deepsea
