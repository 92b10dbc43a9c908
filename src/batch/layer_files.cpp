#include "deepsea/batch/layer_files.h"

#include <algorithm>

#include "deepsea/core/error.h"

namespace deepsea {

const std::vector<std::string>& camera_layer_names() {
    static const std::vector<std::string> names{"raw", "linear_dn", "noise_free"};
    return names;
}

std::vector<std::string> all_layer_names(bool camera) {
    std::vector<std::string> all = layer_names();
    if (camera) all.insert(all.end(), camera_layer_names().begin(), camera_layer_names().end());
    return all;
}

namespace {

bool named(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

bool is_camera_layer(const std::string& name) { return named(camera_layer_names(), name); }

}  // namespace

LayerSet LayerOutput::compositor_set() const {
    for (const std::string& n : names)
        if (n != "final" && !is_camera_layer(n)) return LayerSet::All;
    return LayerSet::Final;
}

CameraLayerSet LayerOutput::camera_set() const {
    return {named(names, "raw"), named(names, "linear_dn"), named(names, "noise_free")};
}

std::string LayerOutput::describe() const {
    if (all()) return "all";
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : ",") + n;
    return s;
}

std::vector<std::string> parse_layer_set(const std::string& list, bool camera) {
    const std::vector<std::string> known = all_layer_names(camera);
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
        if (it == known.end() && is_camera_layer(name)) {
            throw ConfigError("--layer-set: layer '" + name +
                              "' is the camera stage's: give --camera a YAML whose camera "
                              "section has lens, sensor or processing");
        }
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
                  const LayerOutput& out, const CameraOutput* camera) {
    const std::vector<std::string> rgb{"R", "G", "B"};
    const std::vector<ExrLayer> all{{"final", &l.final, rgb},
                                    {"direct", &l.direct, rgb},
                                    {"forward", &l.forward, rgb},
                                    {"backscatter", &l.backscatter, rgb},
                                    {"transmission", &l.transmission, rgb},
                                    {"depth", &l.depth, {"Z"}},
                                    {"normal", &l.normal, {"X", "Y", "Z"}},
                                    {"snow", &l.snow, rgb},
                                    {"snow_id", &l.snow_id, {"id"}}};
    std::vector<ExrLayer> chosen;
    for (const ExrLayer& layer : all) {
        if (!named(out.names, layer.name)) continue;
        // Snow's layers exist only with marine snow on: "all" leaves them out without it.
        if (layer.image->empty() && (layer.name == "snow" || layer.name == "snow_id")) {
            if (out.all()) continue;
            throw InputError(path + ": layer '" + layer.name +
                             "' is marine snow's: render with --snow");
        }
        chosen.push_back(layer);
    }
    // Through a port, with every layer: which pixels see the input (docs/ports.md).
    if (!l.mask.empty() && out.compositor_set() == LayerSet::All && out.all())
        chosen.push_back({"mask", &l.mask, {"Y"}});
    if (camera) {
        for (const ExrLayer& layer :
             {ExrLayer{"raw", &camera->raw, rgb}, ExrLayer{"linear_dn", &camera->linear_dn, rgb},
              ExrLayer{"noise_free", &camera->noise_free, rgb}}) {
            if (named(out.names, layer.name)) chosen.push_back(layer);
        }
    } else {
        for (const std::string& n : camera_layer_names())
            if (named(out.names, n))
                throw InputError(path + ": layer '" + n + "' is the camera stage's: none given");
    }
    write_exr_layers(path, chosen, meta, out.half);
}

}  // namespace deepsea
