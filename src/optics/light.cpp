#include "deepsea/optics/light.h"

#include <algorithm>
#include <cmath>

#include "deepsea/optics/lamp.h"

namespace deepsea {

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;
}

namespace {

/// Rid's value at `deg` degrees (radians `theta_rad`), the table's interval found by
/// upper(deg): the first index whose angle exceeds deg (std::upper_bound's).
template <class Upper>
double rid_at(const Rid& r, double theta_rad, Upper upper) {
    const double deg = theta_rad * kRadToDeg;
    if (deg > r.cutoff_deg) return 0.0;
    if (r.kind == Rid::Kind::Gaussian) return gaussian_rid(theta_rad, r.sigma_deg / kRadToDeg);
    if (r.angle_deg.empty()) return 0.0;
    if (deg <= r.angle_deg.front()) return r.value.front();
    if (deg > r.angle_deg.back()) return 0.0;
    const std::size_t i = upper(deg);  // angle_deg[i-1] <= deg < [i]
    if (i >= r.angle_deg.size()) return r.value.back();
    const double a0 = r.angle_deg[i - 1], a1 = r.angle_deg[i];
    const double w = a1 > a0 ? (deg - a0) / (a1 - a0) : 0.0;
    return r.value[i - 1] + w * (r.value[i] - r.value[i - 1]);
}

/// Buckets a degree.
constexpr double kBucketsPerDeg = 4.0;

}  // namespace

double Rid::operator()(double theta_rad) const {
    return rid_at(*this, theta_rad, [&](double deg) {
        return std::size_t(std::upper_bound(angle_deg.begin(), angle_deg.end(), deg) -
                           angle_deg.begin());
    });
}

RidRows::RidRows(const Rid& rid) : m_rid(rid) {
    const std::vector<double>& a = rid.angle_deg;
    // (an unsorted table, or angles beyond a float's reach of buckets: every angle searched)
    if (rid.kind != Rid::Kind::Table || a.empty() || !std::is_sorted(a.begin(), a.end()) ||
        !(a.back() < 1e6))
        return;
    const int buckets = int(std::max(a.back(), 180.0) * kBucketsPerDeg) + 2;
    m_start.resize(buckets);
    for (int q = 0; q < buckets; ++q) {
        const double lo = q / kBucketsPerDeg;
        m_start[q] = int(std::lower_bound(a.begin(), a.end(), lo) - a.begin());
    }
}

void RidRows::operator()(int n, const float* theta_rad, float* out) const {
    if (m_start.empty()) {
        for (int u = 0; u < n; ++u) out[u] = float(m_rid(double(theta_rad[u])));
        return;
    }
    const std::vector<double>& a = m_rid.angle_deg;
    const std::size_t size = a.size();
    const int last = int(m_start.size()) - 1;
    // Bucket q = floor(4 deg) (exact: a product by a power of two) holds deg >= q / 4, so the
    // angles below q / 4 lie at or below deg; the steps then go where std::upper_bound would
    // (its predicate, deg < a_i: a NaN steps to the end, as there).
    const auto upper = [&](double deg) {
        const double b = deg * kBucketsPerDeg;
        const int q = !(b > 0.0) ? 0 : b >= double(last) ? last : int(b);
        std::size_t i = std::size_t(m_start[q]);
        while (i < size && !(deg < a[i])) ++i;
        return i;
    };
    for (int u = 0; u < n; ++u) out[u] = float(rid_at(m_rid, double(theta_rad[u]), upper));
}

Rgb Light::intensity_toward(const Vec3& w) const {
    return intensity * rid(lamp_angle(dot(direction, w)));
}

}  // namespace deepsea
