#include "deepsea/bake/lattice_rule.h"

#include <algorithm>
#include <cmath>

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
