#include "deepsea/optics/light.h"

#include <algorithm>
#include <cmath>

#include "deepsea/optics/lamp.h"

namespace deepsea {

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;
}

double Rid::operator()(double theta_rad) const {
    const double deg = theta_rad * kRadToDeg;
    if (deg > cutoff_deg) return 0.0;
    if (kind == Kind::Gaussian) return gaussian_rid(theta_rad, sigma_deg / kRadToDeg);
    if (angle_deg.empty()) return 0.0;
    if (deg <= angle_deg.front()) return value.front();
    if (deg > angle_deg.back()) return 0.0;
    const auto it = std::upper_bound(angle_deg.begin(), angle_deg.end(), deg);
    const std::size_t i = std::size_t(it - angle_deg.begin());  // angle_deg[i-1] <= deg < [i]
    if (i >= angle_deg.size()) return value.back();
    const double a0 = angle_deg[i - 1], a1 = angle_deg[i];
    const double w = a1 > a0 ? (deg - a0) / (a1 - a0) : 0.0;
    return value[i - 1] + w * (value[i] - value[i - 1]);
}

Rgb Light::intensity_toward(const Vec3& w) const {
    return intensity * rid(lamp_angle(dot(direction, w)));
}

}  // namespace deepsea
