#include "snow_config.h"

#include <sstream>

#include "deepsea/core/error.h"
#include "deepsea/optics/schema.h"

namespace deepsea {

using yaml::Field;
using yaml::MapView;

std::optional<Snow> parse_snow(const yaml::Document& doc, const Field& f) {
    const auto preset = [&](const Field& name) {
        try {
            return snow_preset(doc.string(name), "snow");
        } catch (const ConfigError& e) {
            doc.fail(name, e.what());
        }
    };
    if (f.node.IsScalar()) {
        if (doc.string(f) == "off") return std::nullopt;
        Snow s = preset(f);
        validate(s);
        return s;
    }
    const MapView m(doc, f, schema::kSnow);
    Snow s;
    s.name = "custom";
    const Field* p = m.opt("preset");
    if (p)
        s = preset(*p);
    else
        m.need("concentration");  // throws: required without a preset
    bool changed = false;
    const auto value = [&](const char* key, double& v) {
        if (const Field* x = m.opt(key)) {
            const double given = doc.number(*x);
            changed |= given != v;
            v = given;
        }
    };
    value("concentration", s.concentration);
    value("d_min_mm", s.d_min_mm);
    value("d_max_mm", s.d_max_mm);
    value("slope", s.slope);
    value("albedo", s.albedo);
    value("max_distance_m", s.max_distance_m);
    if (changed) s.name = "custom";  // a preset's values changed: no longer the preset
    // How it is drawn, not what it is: the preset's name stays.
    if (const Field* x = m.opt("streaks")) s.streaks = doc.boolean(*x);
    if (const Field* x = m.opt("exposure_time_ms")) s.exposure_time_ms = doc.number(*x);
    if (const Field* x = m.opt("frame_rate_hz")) s.frame_rate_hz = doc.number(*x);
    validate(s);
    return s;
}

void write_snow(std::ostream& o, const Snow& s) {
    const auto num = [](double v) {
        std::ostringstream t;
        t.precision(17);
        t << v;
        return t.str();
    };
    o << "snow:\n";
    if (s.name != "custom") o << "  preset: " << s.name << "\n";
    o << "  concentration: " << num(s.concentration) << "\n"
      << "  d_min_mm: " << num(s.d_min_mm) << "\n"
      << "  d_max_mm: " << num(s.d_max_mm) << "\n"
      << "  slope: " << num(s.slope) << "\n"
      << "  albedo: " << num(s.albedo) << "\n"
      << "  max_distance_m: " << num(s.max_distance_m) << "\n";
    if (s.streaks) o << "  streaks: true\n";
    if (s.exposure_time_ms != Snow{}.exposure_time_ms)
        o << "  exposure_time_ms: " << num(s.exposure_time_ms) << "\n";
    if (s.frame_rate_hz != 0.0) o << "  frame_rate_hz: " << num(s.frame_rate_hz) << "\n";
}

}  // namespace deepsea
