#include "deepsea/batch/layer_files.h"

#include <algorithm>

#include "deepsea/core/error.h"

namespace deepsea {

LayerSet LayerOutput::compositor_set() const {
    for (const std::string& n : names)
        if (n != "final") return LayerSet::All;
    return LayerSet::Final;
}

std::string LayerOutput::describe() const {
    if (all()) return "all";
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : ",") + n;
    return s;
}

std::vector<std::string> parse_layer_set(const std::string& list) {
    const std::vector<std::string>& known = layer_names();
    std::string known_list;
    for (const std::string& n : known) known_list += (known_list.empty() ? "" : ", ") + n;
    std::vector<bool> chosen(known.size(), false);
    std::size_t b = 0;
    bool any = false;
    while (b <= list.size()) {
        const std::size_t e = std::min(list.find(',', b), list.size());
        const std::string name = list.substr(b, e - b);
        b = e + 1;
        if (name == "all") {
            std::fill(chosen.begin(), chosen.end(), true);
            any = true;
            continue;
        }
        const auto it = std::find(known.begin(), known.end(), name);
        if (it == known.end()) {
            throw ConfigError("--layer-set: unknown layer '" + name + "' (layers: " + known_list +
                              ", or all)");
        }
        const std::size_t i = std::size_t(it - known.begin());
        if (chosen[i] && list.find("all") == std::string::npos)
            throw ConfigError("--layer-set: layer '" + name + "' named twice");
        chosen[i] = true;
        any = true;
    }
    if (!any) throw ConfigError("--layer-set: no layer named (layers: " + known_list + ")");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < known.size(); ++i)
        if (chosen[i]) out.push_back(known[i]);
    return out;
}

void write_layers(const std::string& path, const Layers& l, const ImageMetadata& meta,
                  const LayerOutput& out) {
    const std::vector<std::string> rgb{"R", "G", "B"};
    const std::vector<ExrLayer> all{{"final", &l.final, rgb},
                                    {"direct", &l.direct, rgb},
                                    {"forward", &l.forward, rgb},
                                    {"backscatter", &l.backscatter, rgb},
                                    {"transmission", &l.transmission, rgb},
                                    {"depth", &l.depth, {"Z"}},
                                    {"normal", &l.normal, {"X", "Y", "Z"}}};
    std::vector<ExrLayer> chosen;
    for (const ExrLayer& layer : all) {
        if (std::find(out.names.begin(), out.names.end(), layer.name) != out.names.end())
            chosen.push_back(layer);
    }
    write_exr_layers(path, chosen, meta, out.half);
}

}  // namespace deepsea
