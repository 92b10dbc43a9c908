#include "deepsea/bake/higher_orders_check.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "deepsea/bake/bake_ray.h"
#include "deepsea/optics/multiple_scattering.h"

namespace deepsea {

std::vector<int> computed_indices(int n, int stride) {
    std::vector<int> out;
    for (int i = 0; i < n; i += std::max(stride, 1)) out.push_back(i);
    if (out.back() != n - 1) out.push_back(n - 1);
    return out;
}

namespace {

/// Cell of x among the computed indices c: c[a] <= x <= c[a + 1], w the weight of c[a + 1].
void bracket(const std::vector<int>& c, double x, std::size_t& a, double& w) {
    if (c.size() == 1) {
        a = 0, w = 0.0;
        return;
    }
    x = std::clamp(x, double(c.front()), double(c.back()));
    a = std::size_t(std::upper_bound(c.begin(), c.end(), x) - c.begin());
    a = std::min(std::max<std::size_t>(a, 1), c.size() - 1) - 1;
    w = (x - c[a]) / double(c[a + 1] - c[a]);
}

}  // namespace

Rgb MsColumns::at(double x, double y, std::size_t k) const {
    std::size_t a, b;
    double wa, wb;
    bracket(ci, x, a, wa);
    bracket(cj, y, b, wb);
    const std::size_t a1 = std::min(a + 1, ci.size() - 1), b1 = std::min(b + 1, cj.size() - 1);
    const auto v = [&](std::size_t ia, std::size_t jb) {
        return values[(ia * cj.size() + jb) * nk + k];
    };
    const Rgb q[4] = {v(a, b), v(a1, b), v(a, b1), v(a1, b1)};
    const double w[4] = {(1 - wa) * (1 - wb), wa * (1 - wb), (1 - wa) * wb, wa * wb};
    Rgb out;
    for (int c = 0; c < 3; ++c) {
        const bool positive = q[0][c] > 0.0 && q[1][c] > 0.0 && q[2][c] > 0.0 && q[3][c] > 0.0;
        double sum = 0.0;
        for (int n = 0; n < 4; ++n) sum += w[n] * (log && positive ? std::log(q[n][c]) : q[n][c]);
        out[c] = log && positive ? std::exp(sum) : sum;
    }
    return out;
}

std::vector<std::pair<double, double>> ms_check_pixels(const Asset& asset, const MsColumns& ms) {
    const Camera& cam = asset.info.camera;
    const int step = asset.info.lattice.step;
    std::vector<std::pair<std::size_t, std::size_t>> cells;  // (a, b): centre of that cell
    const std::size_t A = ms.ci.size() > 1 ? ms.ci.size() - 1 : 0;
    const std::size_t B = ms.cj.size() > 1 ? ms.cj.size() - 1 : 0;
    if (A == 0 || B == 0) return {};
    const std::size_t m = std::max<std::size_t>(
        1, std::size_t(std::floor(std::sqrt(double(A * B) / double(kMsCheckCells)))));
    for (std::size_t a = m / 2; a < A; a += m)
        for (std::size_t b = m / 2; b < B; b += m) cells.emplace_back(a, b);
    // Where the beams are: the cell under each lamp's axis at 0.5 .. 8 m from the lamp.
    for (const Light& L : asset.info.rig.lights) {
        for (double s : {0.5, 1.0, 2.0, 4.0, 8.0}) {
            const Vec3 P = L.position + L.direction * s;
            if (!(P.z > 0.0)) continue;
            const double x = (cam.fx * P.x / P.z + cam.cx) / step;
            const double y = (cam.fy * P.y / P.z + cam.cy) / step;
            if (!(x >= 0.0 && y >= 0.0 && x <= ms.ci.back() && y <= ms.cj.back())) continue;
            std::size_t a, b;
            double w;
            bracket(ms.ci, x, a, w);
            bracket(ms.cj, y, b, w);
            cells.emplace_back(a, b);
        }
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    std::vector<std::pair<double, double>> pixels;
    for (const auto& [a, b] : cells) {
        // Midway between computed columns (a lattice column's ray where the stride is even,
        // between two lattice columns where it is odd), within the image.
        const double u = 0.5 * (ms.ci[a] + ms.ci[a + 1]) * step;
        const double v = 0.5 * (ms.cj[b] + ms.cj[b + 1]) * step;
        pixels.emplace_back(std::min(u, cam.width - 1.0), std::min(v, cam.height - 1.0));
    }
    std::sort(pixels.begin(), pixels.end());
    pixels.erase(std::unique(pixels.begin(), pixels.end()), pixels.end());
    return pixels;
}

HigherOrderCheck check_higher_orders(const Asset& asset, const MsColumns& ms, const Parallel& par) {
    const BakeInfo& info = asset.info;
    const Lattice& l = info.lattice;
    const std::vector<std::pair<double, double>> pixels = ms_check_pixels(asset, ms);
    HigherOrderCheck check;
    check.done = true;
    check.paths = info.higher_orders.paths * kMsCheckPathFactor;
    if (pixels.empty()) return check;
    // Depth samples compared: those nearest 2, 4 and 8 m (the single-scattering check's planes)
    // and z_max (open water).
    std::vector<std::size_t> ks;
    for (double z : {2.0, 4.0, 8.0}) {
        if (z >= l.z_max()) continue;
        const auto it = std::lower_bound(l.z.begin(), l.z.end(), z);
        ks.push_back(std::size_t(it - l.z.begin()));
    }
    ks.push_back(l.z.size() - 1);
    std::sort(ks.begin(), ks.end());
    ks.erase(std::unique(ks.begin(), ks.end()), ks.end());

    const Transport transport(info.rig, info.water);
    const MonteCarlo mc{check.paths, info.higher_orders.seed, info.higher_orders.wall};
    std::vector<double> err(pixels.size()), noise(pixels.size());
    parallel_for(
        pixels.size(),
        [&](std::size_t begin, std::size_t end) {
            std::vector<double> t(ks.size());
            for (std::size_t n = begin; n < end; ++n) {
                const auto [u, v] = pixels[n];
                const BakeRay ray = bake_ray(info.camera, info.port, u, v);
                for (std::size_t q = 0; q < ks.size(); ++q) t[q] = ray.path(l.z[ks[q]]);
                // Streams after every lattice column's: independent of the computed columns.
                const std::uint64_t stream = std::uint64_t(l.ni) * std::uint64_t(l.nj) + n;
                const Estimate e = higher_orders_cumulative(transport, ray.origin, ray.dir, t, mc,
                                                            stream, par.stop);
                double worst = 0.0, se = 0.0;
                for (std::size_t q = 0; q < ks.size(); ++q) {
                    const Rgb interp = ms.at(u / l.step, v / l.step, ks[q]);
                    const Rgb single = asset.sample(u, v, l.z[ks[q]]);
                    for (int c = 0; c < 3; ++c) {
                        const double total = single[c] + e.value[q][c];
                        if (!(total > 0.0)) continue;
                        worst = std::max(worst, std::abs(interp[c] - e.value[q][c]) / total);
                        if (q + 1 == ks.size()) se += e.std_error[q][c] / total / 3.0;
                    }
                }
                err[n] = worst;
                noise[n] = se;
            }
        },
        par.or_grain(1));
    double sum = 0.0, sum_noise = 0.0;
    for (std::size_t n = 0; n < pixels.size(); ++n) {
        sum += err[n];
        sum_noise += noise[n];
        if (err[n] > check.max_rel) {
            check.max_rel = err[n];
            check.max_u = pixels[n].first;
            check.max_v = pixels[n].second;
        }
    }
    check.columns = long(pixels.size());
    check.mean_rel = sum / double(pixels.size());
    check.rel_std_error = sum_noise / double(pixels.size());
    return check;
}

}  // namespace deepsea
