#include "deepsea/bake/lattice_rule.h"

#include <algorithm>
#include <cmath>

#include "deepsea/asset/lattice.h"
#include "deepsea/bake/higher_orders.h"
#include "deepsea/optics/phase_sampling.h"

namespace deepsea {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

}  // namespace

double profile_detail(const Rid& rid) {
    if (rid.kind == Rid::Kind::Gaussian) return rid.sigma_deg * kDegree;
    // A table is linear between knots: its bend sits at the knots, as a change of slope spread
    // over the neighbouring intervals (the second divided difference).
    const std::vector<double>& a = rid.angle_deg;
    const std::vector<double>& f = rid.value;
    double peak = 0.0, bend = 0.0;
    for (double x : f) peak = std::max(peak, x);
    for (std::size_t k = 1; k + 1 < a.size(); ++k) {
        const double s0 = (f[k] - f[k - 1]) / ((a[k] - a[k - 1]) * kDegree);
        const double s1 = (f[k + 1] - f[k]) / ((a[k + 1] - a[k]) * kDegree);
        bend = std::max(bend, std::abs(2.0 * (s1 - s0) / ((a[k + 1] - a[k - 1]) * kDegree)));
    }
    if (!(peak > 0.0) || !(bend > 0.0)) return 3.14159265358979323846;  // flat: no detail
    return std::sqrt(peak / bend);
}

int auto_step(const Camera& cam, const Rig& rig) {
    double detail = 3.14159265358979323846;
    for (const Light& l : rig.lights) detail = std::min(detail, profile_detail(l.rid));
    const double pixel = 1.0 / std::min(cam.fx, cam.fy);  // radians per pixel on the axis
    const double step = std::floor(kStepPerDetail * detail / pixel);
    return int(std::clamp(step, 1.0, double(kMaxAutoStep)));
}

namespace {

/// Least s / t along lamp L's axis where it is in the camera's view (pixel within the image,
/// or half an image beyond: the beam's flank is seen there) and its light not yet negligible
/// (exp(-c_min (s + t)) > 1e-3); 1 where the axis is never in view. s from 0.1 m: the first
/// centimetres next to the lamp are too short a stretch of beam to matter.
double parallax(const Camera& cam, const Light& L, const Water& water) {
    const double c_min = water.c.min();
    const double reach = c_min > 0.0 ? std::min(std::log(1e3) / c_min, 200.0) : 200.0;
    double least = 1.0;
    bool seen = false;
    constexpr int kM = 96;
    for (int m = 0; m <= kM; ++m) {
        const double s = 0.1 * std::pow(reach / 0.1, double(m) / kM);
        const Vec3 P = L.position + L.direction * s;
        const double t = length(P);
        if (!(P.z > 0.0) || s + t > reach) continue;
        const double u = cam.fx * P.x / P.z + cam.cx, v = cam.fy * P.y / P.z + cam.cy;
        if (u < -0.5 * cam.width || u > 1.5 * cam.width || v < -0.5 * cam.height ||
            v > 1.5 * cam.height)
            continue;
        least = seen ? std::min(least, s / t) : s / t;
        seen = true;
    }
    return seen ? std::min(least, 1.0e3) : 1.0;
}

}  // namespace

double ms_detail(const Camera& cam, const Rig& rig, const Water& water) {
    double w = 0.0;
    const double median =
        std::acos(std::clamp(PhaseSampler(water.phase).sample_cos(0.5, w), -1.0, 1.0));
    double detail = 3.14159265358979323846;
    for (const Light& l : rig.lights) {
        const double beam = profile_detail(l.rid) * parallax(cam, l, water);
        detail = std::min(detail, std::hypot(beam, median));
    }
    return detail;
}

int auto_ms_stride(const Camera& cam, const Rig& rig, const Water& water, int step, int paths) {
    const double spacing =
        std::min(kMsSpacingPerDetail * ms_detail(cam, rig, water), kMaxMsSpacing);
    const double pixels = spacing * std::min(cam.fx, cam.fy);
    int stride = std::max(1, int(std::floor(pixels / std::max(step, 1))));
    const int ni = lattice_count(cam.width, step), nj = lattice_count(cam.height, step);
    while (stride < std::max(ni, nj) &&
           double(higher_order_columns(ni, nj, stride)) * std::max(paths, 1) > kMsPathBudget)
        ++stride;
    return stride;
}

bool Refinement::changed() const { return step > 0 || depth_samples > 0; }

bool meets_bar(const LatticeCheck& c) {
    return c.mean_rel <= kBarMeanRel && c.max_rel <= kBarMaxRel;
}

Refinement refine(const LatticeCheck& c, int step, int K, bool step_auto, bool depth_auto) {
    // How far each part is from 70 % of the bar (mean and max, whichever is worse): > 1 misses.
    const auto excess = [](double mean, double max) {
        return std::max(mean / (kRefineTarget * kBarMeanRel), max / (kRefineTarget * kBarMaxRel));
    };
    const double depth = excess(c.columns_mean_rel, c.columns_max_rel);
    const double all = excess(c.mean_rel, c.max_rel);
    Refinement r;
    if (depth_auto && depth > 1.0) {
        r.depth_samples = std::min(4096, std::max(K + 1, int(std::ceil(K * std::sqrt(depth)))));
        if (r.depth_samples == K) r.depth_samples = 0;
    }
    // What the columns do not explain is the xy interpolation's.
    if (step_auto && step > 1 && all > 1.0 &&
        (depth <= 1.0 || all > 2.0 * depth || r.depth_samples == 0)) {
        r.step = std::clamp(int(std::floor(step / std::sqrt(all))), 1, step - 1);
    }
    return r;
}

}  // namespace deepsea
