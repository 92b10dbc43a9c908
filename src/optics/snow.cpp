#include "deepsea/optics/snow.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "deepsea/optics/lamp.h"
#include "deepsea/optics/schema.h"

namespace deepsea {

namespace {

std::string num(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

void require(bool ok, const std::string& key, const std::string& what, double v) {
    if (!ok) throw SchemaError("snow." + key, "must be " + what + ", got " + num(v));
}

/// The presets (docs/snow-shadows.md, "Marine snow", where each number comes from).
Snow preset(const std::string& name) {
    Snow s;
    s.name = name;
    if (name == "abyssal") {
        s.concentration = 200.0;  // 0.2 per litre larger than 0.5 mm
        s.d_min_mm = 0.5;
        s.d_max_mm = 5.0;
        s.slope = 3.5;
        s.max_distance_m = 4.0;
    } else if (name == "nepheloid") {
        s.concentration = 2000.0;  // 2 per litre
        s.d_min_mm = 0.5;
        s.d_max_mm = 5.0;
        s.slope = 3.2;
        s.max_distance_m = 3.0;
    } else if (name == "plume") {
        s.concentration = 5000.0;  // 5 per litre larger than 0.25 mm: sediment flocs
        s.d_min_mm = 0.25;
        s.d_max_mm = 3.0;
        s.slope = 3.0;
        s.max_distance_m = 2.0;
    } else {
        s.concentration = -1.0;
    }
    return s;
}

}  // namespace

const std::vector<std::string>& snow_preset_names() {
    static const std::vector<std::string> names{"abyssal", "nepheloid", "plume"};
    return names;
}

Snow snow_preset(const std::string& name, const std::string& key) {
    const Snow s = preset(name);
    if (s.concentration < 0.0) {
        std::string list;
        for (const std::string& n : snow_preset_names()) list += (list.empty() ? "" : ", ") + n;
        throw ConfigError(key + ": unknown marine snow preset '" + name + "' (presets: " + list +
                          ", or off)");
    }
    return s;
}

void validate(const Snow& s) {
    require(s.concentration > 0.0 && s.concentration <= 1e6, "concentration",
            "in (0, 1e6] particles per m^3", s.concentration);
    require(s.d_min_mm > 0.0 && s.d_min_mm <= 100.0, "d_min_mm", "in (0, 100] mm", s.d_min_mm);
    require(s.d_max_mm > s.d_min_mm && s.d_max_mm <= 100.0, "d_max_mm",
            "> d_min_mm and at most 100 mm", s.d_max_mm);
    require(s.slope >= 0.0 && s.slope <= 6.0, "slope", "in [0, 6]", s.slope);
    require(s.albedo > 0.0 && s.albedo <= 1.0, "albedo", "in (0, 1]", s.albedo);
    require(s.max_distance_m > kSnowNearM && s.max_distance_m <= 100.0, "max_distance_m",
            "in (0.1, 100] metres", s.max_distance_m);
    if (s.phase.kind == PhaseKind::HenyeyGreenstein)
        require(std::fabs(s.phase.g) < 1.0, "phase.g", "in (-1, 1)", s.phase.g);
    require(s.exposure_time_ms > 0.0 && s.exposure_time_ms <= 1e4, "exposure_time_ms",
            "in (0, 10000] ms", s.exposure_time_ms);
    require(s.frame_rate_hz == 0.0 || (s.frame_rate_hz > 0.0 && s.frame_rate_hz <= 1e4),
            "frame_rate_hz", "in (0, 10000] frames per second", s.frame_rate_hz);
}

SnowSizes::SnowSizes(const Snow& s)
    : m_a(s.d_min_mm * 1e-3),
      m_b(s.d_max_mm * 1e-3),
      m_k(1.0 - s.slope),  // the CDF goes as D^(1 - slope)
      m_ak(std::pow(m_a, m_k)),
      m_bk(std::pow(m_b, m_k)) {}

double SnowSizes::operator()(double q) const {
    if (std::fabs(m_k) < 1e-9) return m_a * std::pow(m_b / m_a, q);
    return std::pow(m_ak + q * (m_bk - m_ak), 1.0 / m_k);
}

double snow_diameter(const Snow& s, double q) { return SnowSizes(s)(q); }

double view_volume(const Camera& c, double z0, double z1) {
    return (double(c.width) / c.fx) * (double(c.height) / c.fy) * (z1 * z1 * z1 - z0 * z0 * z0) /
           3.0;
}

double visible_volume(const Camera& c, const std::vector<float>& zdepth, double z_near,
                      double z_far) {
    const double z03 = z_near * z_near * z_near;
    double sum = 0.0;
    for (const float d : zdepth) {
        const double z = (std::isfinite(d) && d > 0.0f) ? std::fmin(double(d), z_far) : z_far;
        if (z > z_near) sum += z * z * z - z03;
    }
    return sum / (3.0 * c.fx * c.fy);
}

namespace {

/// lamp_term with no Lambert cosine (a sphere faces every lamp), per channel.
Rgb sphere_irradiance(const Light& L, const Water& water, double d1, double cos_theta) {
    const double rid = L.rid(lamp_angle(cos_theta));
    const double spread = lamp_spread(d1, 1.0);
    return {lamp_term(L.intensity.r, rid, spread, water.c.r, d1),
            lamp_term(L.intensity.g, rid, spread, water.c.g, d1),
            lamp_term(L.intensity.b, rid, spread, water.c.b, d1)};
}

}  // namespace

Rgb lamp_irradiance_at(const Light& L, const Water& water, const Vec3& X, Vec3* w_out) {
    const Vec3 lx = X - L.position;
    const double d1 = length(lx);
    if (!(d1 > 0.0)) return {};
    if (w_out) *w_out = lx / d1;
    const auto g = particle_geometry(vec3t(X), 0.0, vec3t(L.position), vec3t(L.direction));
    return sphere_irradiance(L, water, g.d1, g.cos_theta);
}

Rgb particle_radiance(const Rig& rig, const Water& water, const Snow& snow, const Vec3& X) {
    const double d2 = length(X);
    if (!(d2 > 0.0)) return {};
    Rgb sum;
    for (const Light& L : rig.lights) {
        const auto g = particle_geometry(vec3t(X), 1.0 / d2, vec3t(L.position), vec3t(L.direction));
        if (!(g.d1 > 0.0)) continue;
        sum += sphere_irradiance(L, water, g.d1, g.cos_theta) * snow.phase(g.cos_psi);
    }
    return sum * snow.albedo;
}

Rgb particle_radiance(const Rig& rig, const Water& water, const Snow& snow, const Vec3& X,
                      const std::vector<LampField>& scattered) {
    Rgb sum = particle_radiance(rig, water, snow, X);
    const double d2 = length(X);
    if (!(d2 > 0.0) || scattered.empty()) return sum;
    if (scattered.size() != rig.lights.size())
        throw std::invalid_argument("particle_radiance: one lamp field per lamp");
    const double k1 = snow.phase.legendre_moment(1), k2 = snow.phase.legendre_moment(2);
    const Vec3 v = X / d2;
    for (std::size_t l = 0; l < scattered.size(); ++l) {
        if (scattered[l].empty()) continue;
        const Light& L = rig.lights[l];
        Vec3 ex, ey;
        lamp_frame(L.direction, ex, ey);
        const Vec3& a = L.direction;
        const Vec3 q = X - L.position;
        double coef[3 * kQuadraticCount];
        lamp_field_quadratic(LampFieldView<double>(scattered[l]), ex.x, ex.y, ex.z, ey.x, ey.y,
                             ey.z, a.x, a.y, a.z, dot(q, ex), dot(q, ey), dot(q, a), coef, 1);
        for (int c = 0; c < 3; ++c) {
            sum[c] += snow.albedo * L.intensity[c] *
                      quadratic_in_scatter(coef + c * kQuadraticCount, 1, k1, k2, v.x, v.y, v.z);
        }
    }
    return sum;
}

}  // namespace deepsea
