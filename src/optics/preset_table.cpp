#include "preset_table.h"

#include "deepsea/core/error.h"

namespace deepsea::presets {

std::vector<std::string> types(const Row* rows, std::size_t n) {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < n; ++i) names.emplace_back(rows[i].type);
    return names;
}

Water water(const Row* rows, std::size_t n, const std::string& type, const char* name_prefix,
            const char* family, const std::vector<std::string>& known) {
    for (std::size_t i = 0; i < n; ++i) {
        const Row& r = rows[i];
        if (type == r.type) {
            Water w;
            w.name = std::string(name_prefix) + r.type;
            w.c = r.c;
            w.b = r.b;
            w.phase.kind = r.phase;
            return w;
        }
    }
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    throw ConfigError("unknown " + std::string(family) + " water type '" + type +
                      "' (known: " + list + ")");
}

}  // namespace deepsea::presets
