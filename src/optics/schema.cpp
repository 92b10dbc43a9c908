#include "deepsea/optics/schema.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "deepsea/core/image.h"

namespace deepsea {

namespace {

const char* const kChannel[] = {"R", "G", "B"};

void require_non_negative(const Rgb& x, const std::string& key) {
    for (int i = 0; i < 3; ++i)
        if (!(x[i] >= 0.0))
            throw SchemaError(key, std::string("must be >= 0 (") + kChannel[i] + " is " +
                                       short_number(x[i]) + ")");
}

void validate_rid(const Rid& rid, const std::string& light) {
    const std::string key = light + ".rid";
    if (rid.kind == Rid::Kind::Gaussian) {
        if (!(rid.sigma_deg > 0.0))
            throw SchemaError(key + ".gaussian.sigma_deg", "must be > 0 degrees");
    } else {
        const std::string angles = key + ".table.angle_deg", values = key + ".table.value";
        for (std::size_t i = 0; i < rid.angle_deg.size(); ++i) {
            const double x = rid.angle_deg[i];
            const std::string at = angles + "[" + std::to_string(i) + "]";
            if (!(x >= 0.0 && x <= 180.0)) throw SchemaError(at, "must be in [0, 180] degrees");
            if (i > 0 && x <= rid.angle_deg[i - 1])
                throw SchemaError(at, "angles must be strictly ascending");
        }
        for (std::size_t i = 0; i < rid.value.size(); ++i)
            if (!(rid.value[i] >= 0.0))
                throw SchemaError(values + "[" + std::to_string(i) + "]", "must be >= 0");
        if (rid.angle_deg.size() < 2) throw SchemaError(angles, "needs at least 2 angles");
        if (rid.value.size() != rid.angle_deg.size())
            throw SchemaError(values, "has " + std::to_string(rid.value.size()) + " values for " +
                                          std::to_string(rid.angle_deg.size()) + " angles");
    }
    if (!(rid.cutoff_deg > 0.0 && rid.cutoff_deg <= 180.0))
        throw SchemaError(light + ".cutoff_deg", "must be in (0, 180] degrees");
}

}  // namespace

void validate(const Camera& c) {
    if (c.width <= 0)
        throw SchemaError("camera.width", "must be > 0, got " + std::to_string(c.width));
    if (c.height <= 0)
        throw SchemaError("camera.height", "must be > 0, got " + std::to_string(c.height));
    if (c.width > kMaxImageSide || c.height > kMaxImageSide ||
        (long double)c.width * c.height > kMaxImagePixels) {
        throw SchemaError("camera.width", std::to_string(c.width) + "x" + std::to_string(c.height) +
                                              " is larger than deepsea's limit of " +
                                              std::to_string(kMaxImagePixels / 1000000) +
                                              " megapixels (at most " +
                                              std::to_string(kMaxImageSide) + " on a side)");
    }
    if (!(c.fx > 0.0) || !std::isfinite(c.fx))
        throw SchemaError("camera.fx", "must be > 0, got " + short_number(c.fx));
    if (!(c.fy > 0.0) || !std::isfinite(c.fy))
        throw SchemaError("camera.fy", "must be > 0, got " + short_number(c.fy));
    if (!std::isfinite(c.cx)) throw SchemaError("camera.cx", "must be a finite number");
    if (!std::isfinite(c.cy)) throw SchemaError("camera.cy", "must be a finite number");
    // The ray through a pixel edge, per axis: tan(angle) = |edge - centre| / focal length.
    const double tan_max = std::tan(kMaxRayAngleDeg * M_PI / 180.0);
    const auto check_axis = [&](const char* key, const char* f, double focal, double centre,
                                int size) {
        const double off = std::max(std::fabs(-0.5 - centre), std::fabs(size - 0.5 - centre));
        if (!(off <= tan_max * focal)) {
            char deg[32];  // 89.99, not 89.9999641901378
            std::snprintf(deg, sizeof deg, "%.4g", std::atan2(off, focal) * 180.0 / M_PI);
            throw SchemaError(key,
                              "rays through the image's edges reach " + std::string(deg) +
                                  " degrees from the axis (" + f + " = " + short_number(focal) +
                                  ", centre " + short_number(centre) + ", " + std::to_string(size) +
                                  " pixels); deepsea's limit is " + short_number(kMaxRayAngleDeg) +
                                  " degrees per axis: give a longer focal length");
        }
    };
    check_axis("camera.fx", "fx", c.fx, c.cx, c.width);
    check_axis("camera.fy", "fy", c.fy, c.cy, c.height);
}

void validate(const Rig& rig) {
    if (rig.lights.empty()) throw SchemaError("rig.lights", "needs at least one light");
    std::map<std::string, std::size_t> seen;
    for (std::size_t i = 0; i < rig.lights.size(); ++i) {
        const Light& l = rig.lights[i];
        const std::string key = "rig.lights[" + std::to_string(i) + "]";
        const Vec3& p = l.position;
        const std::string where =
            "[" + short_number(p.x) + ", " + short_number(p.y) + ", " + short_number(p.z) + "] m";
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw SchemaError(key + ".position",
                              "lamp '" + l.name + "' at " + where + ": coordinates must be finite");
        if (!(length(p) >= kLampNearFieldRadius))
            throw SchemaError(key + ".position",
                              "lamp '" + l.name + "' at " + where + " is " +
                                  short_number(length(p)) +
                                  " m from the camera centre, inside the near-field limit of " +
                                  short_number(kLampNearFieldRadius) +
                                  " m (single-scattering backscatter diverges there)");
        if (!(length(p) <= kMaxLampDistance))
            throw SchemaError(
                key + ".position",
                "lamp '" + l.name + "' at " + where + " is " + short_number(length(p)) +
                    " m from the camera centre, beyond the limit of " +
                    short_number(kMaxLampDistance) + " m (a rig's lamps move with it)");
        const Vec3& d = l.direction;
        if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
            throw SchemaError(key + ".direction", "coordinates must be finite");
        if (!(length(d) > 1e-12) || !std::isfinite(length(d)))
            throw SchemaError(key + ".direction", "must be a non-zero vector of finite length");
        require_non_negative(l.intensity, key + ".intensity");
        for (int c = 0; c < 3; ++c)
            if (!(l.intensity[c] <= kMaxLampIntensity))
                throw SchemaError(key + ".intensity",
                                  std::string("must be at most ") +
                                      short_number(kMaxLampIntensity) + " W/sr per channel (" +
                                      kChannel[c] + " is " + short_number(l.intensity[c]) + ")");
        validate_rid(l.rid, key);
        if (!(l.radius >= 0.0 && l.radius <= kMaxLampRadius))
            throw SchemaError(key + ".radius", "must be in [0, " + short_number(kMaxLampRadius) +
                                                   "] m (the lamp's emitting face)");
        const auto [it, fresh] = seen.emplace(l.name, i);
        if (!fresh)
            throw SchemaError(key, "light name '" + l.name + "' already used by lights[" +
                                       std::to_string(it->second) + "]");
    }
}

void validate(const Water& w) {
    require_non_negative(w.c, "water.attenuation");
    require_non_negative(w.b, "water.scattering");
    for (int i = 0; i < 3; ++i)
        if (w.b[i] > w.c[i])
            throw SchemaError("water.scattering",
                              std::string("scattering must not exceed attenuation (") +
                                  kChannel[i] + ": b = " + short_number(w.b[i]) +
                                  " > c = " + short_number(w.c[i]) + ")");
    if (w.phase.kind == PhaseKind::HenyeyGreenstein && !(w.phase.g > -1.0 && w.phase.g < 1.0))
        throw SchemaError("water.phase.henyey_greenstein.g", "must be in (-1, 1)");
    if (!w.forward.enabled || w.forward.model == ForwardModel::PhaseFunction) return;
    require_non_negative(w.forward.G, "water.forward_scatter.G");
    for (int i = 0; i < 3; ++i)
        if (w.forward.G[i] > w.c[i])
            throw SchemaError("water.forward_scatter.G",
                              std::string("G must not exceed attenuation c (") + kChannel[i] +
                                  ": G = " + short_number(w.forward.G[i]) +
                                  " > c = " + short_number(w.c[i]) + ")");
    if (!(w.forward.k >= 0.0)) throw SchemaError("water.forward_scatter.k", "must be >= 0 rad/m");
}

}  // namespace deepsea
