#include "deepsea/batch/sequence_manifest.h"

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/core/hash.h"
#include "deepsea/core/input_file.h"
#include "deepsea/runtime/lamp_shadows.h"

namespace deepsea {

using nlohmann::json;

std::string poses_hash(const std::vector<FrameJob>& jobs) {
    std::uint64_t h = kFnv1aBasis;
    bool any = false;
    for (const FrameJob& job : jobs) {
        if (!job.pose) {
            h = fnv1a64(std::string_view("none"), h);
            continue;
        }
        any = true;
        const auto add = [&](const CameraPose& p) {
            for (const Vec3& v : {p.origin, p.right, p.down, p.forward}) {
                const double xyz[3] = {v.x, v.y, v.z};
                h = fnv1a64(xyz, sizeof xyz, h);
            }
        };
        add(*job.pose);
        if (job.shutter) {  // motion streaks: the shutter's poses too
            add(job.shutter->open);
            add(job.shutter->close);
        }
    }
    if (!any) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
    return std::string("fnv1a64:") + buf;
}

std::string manifest_to_json(const SequenceManifest& m) {
    json j;
    j["format"] = SequenceManifest::kFormat;
    j["deepsea_version"] = m.deepsea_version;
    j["asset_hash"] = m.asset_hash;
    j["inputs"] = {{"rgb", m.rgb}, {"depth", m.depth}};
    j["camera"] = {{"width", m.camera.width}, {"height", m.camera.height}, {"fx", m.camera.fx},
                   {"fy", m.camera.fy},       {"cx", m.camera.cx},         {"cy", m.camera.cy}};
    j["camera_stage"] = m.camera_stage.empty() ? "none" : m.camera_stage;
    j["port"] = m.port.empty() ? "none" : m.port;
    j["exposure"] = {{"mode", !m.camera_stage.empty() ? "camera"
                              : m.auto_exposure       ? "auto"
                                                      : "fixed"},
                     {"factor", m.exposure},
                     {"chosen_on", m.exposure_frame},
                     {"percentile", m.percentile},
                     {"target", m.target},
                     {"max_clipped", m.max_clipped}};
    j["outputs"] = {{"image", m.image ? m.image_format : "none"},
                    {"bits", m.bits},
                    {"layers", m.layers ? m.layer_set : "none"},
                    {"half", m.half}};
    j["settings"] = {{"forward", m.forward},
                     {"depth_kind", m.depth_kind},
                     {"depth_channel", m.depth_channel},
                     {"depth_scale", m.depth_scale}};
    // Written only when on: a sequence without shadows has the manifest it had before them.
    if (m.shadows) j["settings"]["shadows"] = true;
    if (m.shadows) j["settings"]["shadow_step"] = m.shadow_step;
    if (m.snow != "off")
        j["settings"]["snow"] = {
            {"preset", m.snow}, {"seed", m.snow_seed}, {"focus_distance_m", m.focus_distance_m}};
    for (const auto& [key, v] : m.snow_values) j["settings"]["snow"][key] = v;
    if (!m.poses_hash.empty())
        j["settings"]["poses"] = {{"frames", m.poses}, {"hash", m.poses_hash}};
    j["frames"] = {{"total", m.frames_total}, {"done", m.frames_done}};
    if (m.shard) {
        const ShardRecord& s = *m.shard;
        j["shard"] = {{"index", s.index},
                      {"count", s.count},
                      {"sequence_frames", s.sequence_frames},
                      {"folders", {{"image", s.image_folder}, {"layers", s.layers_folder}}}};
    }
    return j.dump(2) + "\n";
}

std::string shard_manifest_name(int index, int count) {
    char name[96];
    std::snprintf(name, sizeof name, "deepsea-sequence.shard-%04d-of-%04d.json", index, count);
    return name;
}

namespace {

/// j[a][b] as T, InputError naming the file and the key otherwise.
template <class T>
T get(const json& j, const std::string& path, const char* a, const char* b = nullptr) {
    const std::string key = b ? std::string(a) + "." + b : std::string(a);
    const json* v = &j;
    for (const char* k : {a, b}) {
        if (!k) break;
        if (!v->is_object() || !v->contains(k)) throw InputError(path + ": " + key + ": missing");
        v = &(*v)[k];
    }
    try {
        return v->get<T>();
    } catch (const json::exception&) {
        throw InputError(path + ": " + key + ": wrong type (" + v->type_name() + ")");
    }
}

}  // namespace

SequenceManifest manifest_from_json(const std::string& text, const std::string& path) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        throw InputError(path + ": not a deepsea sequence manifest: " + one_line(e.what()));
    }
    if (get<int>(j, path, "format") != SequenceManifest::kFormat) {
        throw InputError(path + ": format " + std::to_string(get<int>(j, path, "format")) +
                         " is not known to this deepsea (it reads format " +
                         std::to_string(SequenceManifest::kFormat) + ")");
    }
    SequenceManifest m;
    m.deepsea_version = get<std::string>(j, path, "deepsea_version");
    m.asset_hash = get<std::string>(j, path, "asset_hash");
    m.rgb = get<std::string>(j, path, "inputs", "rgb");
    m.depth = get<std::string>(j, path, "inputs", "depth");
    m.camera.width = get<int>(j, path, "camera", "width");
    m.camera.height = get<int>(j, path, "camera", "height");
    m.camera.fx = get<double>(j, path, "camera", "fx");
    m.camera.fy = get<double>(j, path, "camera", "fy");
    m.camera.cx = get<double>(j, path, "camera", "cx");
    m.camera.cy = get<double>(j, path, "camera", "cy");
    const std::string mode = get<std::string>(j, path, "exposure", "mode");
    if (mode != "auto" && mode != "fixed" && mode != "camera")
        throw InputError(path + ": exposure.mode: expected auto, fixed or camera, got '" + mode +
                         "'");
    m.auto_exposure = mode == "auto";
    // "camera_stage" came with the camera stage; a manifest from before it had none.
    m.camera_stage = j.contains("camera_stage") ? get<std::string>(j, path, "camera_stage") : "";
    if (m.camera_stage == "none") m.camera_stage.clear();
    // "port" came with rendering through a port; a manifest from before it had none.
    m.port = j.contains("port") ? get<std::string>(j, path, "port") : "";
    if (m.port == "none") m.port.clear();
    if ((mode == "camera") != !m.camera_stage.empty())
        throw InputError(path + ": exposure.mode: '" + mode + "' does not match camera_stage");
    m.exposure = get<double>(j, path, "exposure", "factor");
    if (!(m.exposure >= 0.0)) throw InputError(path + ": exposure.factor: must be >= 0");
    m.exposure_frame = get<std::string>(j, path, "exposure", "chosen_on");
    m.percentile = get<double>(j, path, "exposure", "percentile");
    m.target = get<double>(j, path, "exposure", "target");
    m.max_clipped = get<double>(j, path, "exposure", "max_clipped");
    const std::string image = get<std::string>(j, path, "outputs", "image");
    m.image = image != "none";
    if (m.image) m.image_format = image;
    m.bits = get<int>(j, path, "outputs", "bits");
    const std::string layers = get<std::string>(j, path, "outputs", "layers");
    m.layers = layers != "none";
    if (m.layers) m.layer_set = layers;
    // "half" came with --layer-set; a manifest from before it wrote float layers.
    m.half = j.contains("outputs") && j["outputs"].contains("half")
                 ? get<bool>(j, path, "outputs", "half")
                 : false;
    m.forward = get<bool>(j, path, "settings", "forward");
    // "shadows" came with lamp shadows; absent: off.
    m.shadows =
        j["settings"].contains("shadows") ? get<bool>(j, path, "settings", "shadows") : false;
    // "shadow_step" came with render --shadow-step; absent: the default step.
    m.shadow_step = j["settings"].contains("shadow_step")
                        ? get<int>(j, path, "settings", "shadow_step")
                        : kDefaultShadowStep;
    // "snow" came with marine snow; absent: off.
    if (j["settings"].contains("snow")) {
        m.snow = get<std::string>(j["settings"], path + ": settings", "snow", "preset");
        m.snow_seed = get<std::uint64_t>(j["settings"], path + ": settings", "snow", "seed");
        m.focus_distance_m =
            get<double>(j["settings"], path + ": settings", "snow", "focus_distance_m");
        for (const auto& [key, v] : j["settings"]["snow"].items())
            if (key != "preset" && key != "seed" && key != "focus_distance_m")
                m.snow_values.emplace_back(
                    key, get<double>(j["settings"], path + ": settings", "snow", key.c_str()));
    }
    // "poses" came with render --poses in the manifest; absent: none.
    if (j["settings"].contains("poses")) {
        m.poses = get<int>(j["settings"], path + ": settings", "poses", "frames");
        m.poses_hash = get<std::string>(j["settings"], path + ": settings", "poses", "hash");
    }
    m.depth_kind = get<std::string>(j, path, "settings", "depth_kind");
    m.depth_channel = get<std::string>(j, path, "settings", "depth_channel");
    m.depth_scale = get<double>(j, path, "settings", "depth_scale");
    m.frames_total = get<int>(j, path, "frames", "total");
    m.frames_done = get<int>(j, path, "frames", "done");
    if (j.contains("shard")) {
        ShardRecord s;
        s.index = get<int>(j, path, "shard", "index");
        s.count = get<int>(j, path, "shard", "count");
        s.sequence_frames = get<int>(j, path, "shard", "sequence_frames");
        if (s.count < 1 || s.index < 0 || s.index >= s.count)
            throw InputError(path + ": shard: index " + std::to_string(s.index) + " of " +
                             std::to_string(s.count) + ": need 0 <= index < count");
        const json& shard = j["shard"];
        s.image_folder = get<std::string>(shard, path + ": shard", "folders", "image");
        s.layers_folder = get<std::string>(shard, path + ": shard", "folders", "layers");
        m.shard = s;
    }
    return m;
}

SequenceManifest read_manifest(const std::string& path) {
    return manifest_from_json(read_text_file(path, "a sequence manifest"), path);
}

void write_manifest(const std::string& path, const SequenceManifest& m) {
    write_text_atomically(path, manifest_to_json(m));
}

namespace {

/// Every leaf of `j` as "a.b" -> its JSON text.
void flatten(const json& j, const std::string& prefix, std::map<std::string, std::string>& out) {
    if (!j.is_object()) {
        out[prefix] = j.dump();
        return;
    }
    for (const auto& [k, v] : j.items()) flatten(v, prefix.empty() ? k : prefix + "." + k, out);
}

}  // namespace

std::string first_difference(const SequenceManifest& a, const SequenceManifest& b,
                             const std::vector<std::string>& ignore) {
    json ja = json::parse(manifest_to_json(a)), jb = json::parse(manifest_to_json(b));
    for (const std::string& k : ignore) {
        ja.erase(k);
        jb.erase(k);
    }
    std::map<std::string, std::string> fa, fb;
    flatten(ja, "", fa);
    flatten(jb, "", fb);
    for (const auto& [k, v] : fa) {
        const auto it = fb.find(k);
        const std::string other = it == fb.end() ? "(none)" : it->second;
        if (other != v) return k + ": " + v + " vs " + other;
    }
    for (const auto& [k, v] : fb)
        if (!fa.count(k)) return k + ": (none) vs " + v;
    return "";
}

void check_same_inputs(const SequenceManifest& folder, const SequenceManifest& run,
                       const std::string& path) {
    if (folder.rgb != run.rgb || folder.depth != run.depth) {
        throw ConfigError(path + ": this folder holds the frames of '" + folder.rgb + "' and '" +
                          folder.depth + "', not of '" + run.rgb + "' and '" + run.depth +
                          "'; render into another folder");
    }
}

void check_resumable(const SequenceManifest& folder, const SequenceManifest& run,
                     const std::string& path) {
    check_same_inputs(folder, run, path);
    const auto differ = [&](const std::string& what, const std::string& then,
                            const std::string& now) {
        throw ConfigError(path + ": cannot resume: " + what + " was " + then + ", now " + now +
                          " (render without --resume to start again)");
    };
    const auto num = [](double v) {
        std::ostringstream s;
        s.precision(17);
        s << v;
        return s.str();
    };
    if (folder.deepsea_version != run.deepsea_version)
        differ("the deepsea version", folder.deepsea_version, run.deepsea_version);
    if (folder.asset_hash != run.asset_hash) differ("the asset", folder.asset_hash, run.asset_hash);
    if (!(folder.camera == run.camera))
        differ("the camera", describe(folder.camera), describe(run.camera));
    if (folder.camera_stage != run.camera_stage)
        differ("the camera stage", folder.camera_stage.empty() ? "none" : "one camera",
               run.camera_stage.empty()      ? "none"
               : folder.camera_stage.empty() ? "a camera (--camera's lens, sensor or processing)"
                                             : "another camera (--camera's lens, sensor or "
                                               "processing differ)");
    if (folder.port != run.port)
        differ("the port", folder.port.empty() ? "none" : "one port",
               run.port.empty()      ? "none"
               : folder.port.empty() ? "a port (--camera's camera.port)"
                                     : "another port (--camera's camera.port differs)");
    if (folder.auto_exposure != run.auto_exposure)
        differ("the exposure", folder.auto_exposure ? "auto" : "fixed",
               run.auto_exposure ? "auto" : "fixed");
    if (!folder.auto_exposure && folder.exposure != run.exposure)
        differ("the exposure", num(folder.exposure), num(run.exposure));
    if (folder.auto_exposure &&
        (folder.percentile != run.percentile || folder.target != run.target ||
         folder.max_clipped != run.max_clipped))
        differ("the auto exposure rule", num(folder.percentile) + "/" + num(folder.target),
               num(run.percentile) + "/" + num(run.target));
    if (folder.image != run.image)
        differ("-o", folder.image ? "given" : "not given", run.image ? "given" : "not given");
    if (folder.image && folder.image_format != run.image_format)
        differ("--format", folder.image_format, run.image_format);
    if (folder.image && folder.bits != run.bits)
        differ("--bits", std::to_string(folder.bits), std::to_string(run.bits));
    if (folder.layers != run.layers)
        differ("--layers", folder.layers ? "given" : "not given",
               run.layers ? "given" : "not given");
    if (folder.layers && run.layers && folder.layer_set != run.layer_set)
        differ("--layer-set", folder.layer_set, run.layer_set);
    if (folder.layers && run.layers && folder.half != run.half)
        differ("--half", folder.half ? "given" : "not given", run.half ? "given" : "not given");
    if (folder.forward != run.forward)
        differ("forward scatter", folder.forward ? "on" : "off", run.forward ? "on" : "off");
    if (folder.shadows != run.shadows)
        differ("--shadows", folder.shadows ? "on" : "off", run.shadows ? "on" : "off");
    if (folder.shadows && run.shadows && folder.shadow_step != run.shadow_step)
        differ("--shadow-step", std::to_string(folder.shadow_step),
               std::to_string(run.shadow_step));
    if (folder.snow != run.snow) differ("--snow", folder.snow, run.snow);
    if (folder.snow != "off" && folder.snow_seed != run.snow_seed)
        differ("--snow-seed", std::to_string(folder.snow_seed), std::to_string(run.snow_seed));
    if (folder.snow != "off" && folder.focus_distance_m != run.focus_distance_m)
        differ("focus_distance_m", num(folder.focus_distance_m), num(run.focus_distance_m));
    if (folder.snow != "off" && !folder.snow_values.empty())
        for (const auto& [key, v] : run.snow_values)
            for (const auto& [fkey, fv] : folder.snow_values)
                if (key == fkey && v != fv) differ("snow." + key, num(fv), num(v));
    if (folder.poses_hash != run.poses_hash)
        differ("--poses",
               folder.poses_hash.empty()
                   ? "not given"
                   : std::to_string(folder.poses) + " pose(s) " + folder.poses_hash,
               run.poses_hash.empty()
                   ? "not given"
                   : std::to_string(run.poses) + " pose(s) " + run.poses_hash + " (other poses)");
    if (folder.depth_kind != run.depth_kind)
        differ("--depth-kind", folder.depth_kind, run.depth_kind);
    if (folder.depth_channel != run.depth_channel)
        differ("--depth-channel", "'" + folder.depth_channel + "'", "'" + run.depth_channel + "'");
    if (folder.depth_scale != run.depth_scale)
        differ("--depth-scale", num(folder.depth_scale), num(run.depth_scale));
    const auto shard = [](const SequenceManifest& m) {
        return m.shard ? "shard " + std::to_string(m.shard->index) + "/" +
                             std::to_string(m.shard->count) + " of " +
                             std::to_string(m.shard->sequence_frames) + " frames"
                       : std::string("the whole sequence");
    };
    if (shard(folder) != shard(run)) differ("the part rendered", shard(folder), shard(run));
}

}  // namespace deepsea
