#include "deepsea/io/library_manifest.h"

#include <algorithm>
#include <filesystem>

#include "deepsea/core/error.h"
#include "deepsea/optics/water_presets.h"
#include "yaml_reader.h"

namespace deepsea {

namespace {

namespace fs = std::filesystem;
using yaml::Document;
using yaml::Field;
using yaml::MapView;

const std::vector<std::string> kManifestKeys = {"cameras", "rigs", "waters", "bake"};
const std::vector<std::string> kBakeKeys = {"xy_step",   "depth_samples", "depth_scheme", "z_max",
                                            "tolerance", "scattering",    "paths"};

bool is_preset(const std::string& spec) { return is_water_preset(spec); }

/// A preset's stem is its water name ("jerlov-IB", "deep-clear"), like the stem of
/// volumes/waters/<name>.yaml.
std::string stem(const std::string& spec) {
    if (is_preset(spec)) return water_preset(spec).name;
    return fs::path(spec).stem().string();
}

std::vector<std::string> files(const Document& doc, const MapView& m, const char* key,
                               const fs::path& folder) {
    const Field& f = m.need(key);
    const auto items = doc.list(f);
    if (items.empty()) doc.fail(f, "expected a non-empty list of files");
    std::vector<std::string> out;
    for (const Field& item : items) {
        std::string s = doc.string(item);
        if (!is_preset(s)) {
            s = (folder / s).string();
            if (!fs::exists(s)) doc.fail(item, "missing file " + s);
        } else {
            try {
                water_preset(s);
            } catch (const ConfigError& e) {
                doc.fail(item, e.what());
            }
        }
        out.push_back(s);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

LibraryManifest parse(const Document& doc, const fs::path& folder) {
    if (doc.empty() || !doc.root().node.IsMap())
        doc.fail(doc.root(), "not a manifest (expected " + yaml::join(kManifestKeys) + ")");
    const MapView m(doc, doc.root(), kManifestKeys);
    LibraryManifest out;
    out.cameras = files(doc, m, "cameras", folder);
    out.rigs = files(doc, m, "rigs", folder);
    out.waters = files(doc, m, "waters", folder);
    if (const Field* b = m.opt("bake"); b && !b->node.IsNull()) {
        const MapView bm(doc, *b, kBakeKeys);
        LibraryBakeSettings& s = out.bake;
        if (const Field* x = bm.opt("xy_step")) s.xy_step = doc.integer(*x);
        if (const Field* x = bm.opt("depth_samples")) s.depth_samples = doc.integer(*x);
        if (const Field* x = bm.opt("depth_scheme")) s.depth_scheme = doc.string(*x);
        if (const Field* x = bm.opt("z_max")) s.z_max = doc.string(*x);
        if (const Field* x = bm.opt("tolerance")) s.tolerance = doc.number(*x);
        if (const Field* x = bm.opt("scattering")) s.scattering = doc.string(*x);
        if (const Field* x = bm.opt("paths")) s.paths = doc.integer(*x);
    }
    for (const auto& c : out.cameras)
        for (const auto& r : out.rigs)
            for (const auto& w : out.waters)
                out.entries.push_back(
                    {c, r, w, stem(c) + "__" + stem(r) + "__" + stem(w) + ".vdb"});
    // Two inputs with one stem (cameras/a.yaml and other/a.yaml, or jerlov:IB and
    // jerlov-IB.yaml) would overwrite each other's asset: refuse rather than guess.
    std::vector<std::string> names;
    for (const LibraryEntry& e : out.entries) names.push_back(e.name);
    std::sort(names.begin(), names.end());
    const auto dup = std::adjacent_find(names.begin(), names.end());
    if (dup != names.end())
        throw ConfigError(doc.file() + ": two entries would both write " + *dup +
                          " (inputs with the same file stem)");
    return out;
}

}  // namespace

LibraryManifest load_library_manifest(const std::string& path) {
    return parse(Document::load(path), fs::path(path).parent_path());
}

LibraryManifest parse_library_manifest(const std::string& yaml_text, const std::string& file_name,
                                       const std::string& folder) {
    return parse(Document(yaml_text, file_name), folder);
}

}  // namespace deepsea
