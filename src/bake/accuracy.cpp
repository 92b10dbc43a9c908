#include "deepsea/bake/accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deepsea/bake/bake.h"
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

    const std::vector<int> us = test_coords(cam.width, opt.stride);
    const std::vector<int> vs = test_coords(cam.height, opt.stride);
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
                    const Vec3 ray = cam.ray(u, v);
                    const double stretch = length(ray);
                    // One cumulative integral per pixel serves every scene: sort the path lengths.
                    for (std::size_t r = 0; r < R; ++r) order[r] = r;
                    const auto path = [&](std::size_t r) {
                        return exact_z[r] < 0.0 ? std::max(t_far, z_max * stretch)
                                                : exact_z[r] * stretch;
                    };
                    std::sort(order.begin(), order.end(),
                              [&](std::size_t a, std::size_t b) { return path(a) < path(b); });
                    t.assign(1, 0.0);
                    for (std::size_t r : order) t.push_back(path(r));
                    const auto C = backscatter_cumulative(info.rig, info.water, ray / stretch, t,
                                                          opt.quadrature);
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

}  // namespace deepsea
