#include "deepsea/optics/water_presets.h"

#include "deepsea/core/error.h"
#include "deepsea/optics/deep_ocean.h"
#include "deepsea/optics/jerlov.h"

namespace deepsea {

namespace {

struct Family {
    const char* prefix;
    const std::vector<std::string>& (*types)();
    Water (*water)(const std::string&);
};

const Family kFamilies[] = {
    {"jerlov:", jerlov_types, jerlov_water},
    {"deep:", deep_ocean_types, deep_ocean_water},
};

bool starts_with(const std::string& s, const std::string& prefix) {
    return s.compare(0, prefix.size(), prefix) == 0;
}

}  // namespace

const std::vector<std::string>& water_preset_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const Family& f : kFamilies)
            for (const std::string& t : f.types()) n.push_back(f.prefix + t);
        return n;
    }();
    return names;
}

bool is_water_preset(const std::string& spec) {
    for (const Family& f : kFamilies)
        if (starts_with(spec, f.prefix)) return true;
    return false;
}

Water water_preset(const std::string& spec) {
    for (const Family& f : kFamilies) {
        if (!starts_with(spec, f.prefix)) continue;
        const std::string type = spec.substr(std::string(f.prefix).size());
        for (const std::string& t : f.types())
            if (t == type) return f.water(type);
    }
    std::string known;
    for (const std::string& n : water_preset_names()) known += (known.empty() ? "" : ", ") + n;
    throw ConfigError("unknown water preset '" + spec + "' (known: " + known + ")");
}

}  // namespace deepsea
