// deepsea bake-library: bake every camera x rig x water of a manifest, skipping assets whose
// inputs are unchanged; shardable so that array jobs split a large library without overlap.

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/core/error.h"

namespace deepsea::cli {

namespace {

namespace fs = std::filesystem;

/// One asset of the library.
struct Entry {
    std::string camera, rig, water;  ///< files (or a jerlov: spec for the water)
    std::string name;                ///< <camera>__<rig>__<water>.vdb
};

[[noreturn]] void fail(const std::string& file, const YAML::Node& n, const std::string& key,
                       const std::string& problem) {
    throw ConfigError(file + ":" + std::to_string(n.Mark().line + 1) + ": " + key + ": " + problem);
}

std::string stem(const std::string& spec) {
    if (spec.rfind("jerlov:", 0) == 0) return "jerlov-" + spec.substr(7);
    return fs::path(spec).stem().string();
}

/// Manifest keys (paths relative to the manifest):
///   cameras, rigs, waters   lists of YAML files (waters also jerlov:<TYPE>), each non-empty
///   bake                    optional map: xy_step, depth_samples, depth_scheme, z_max
///                           (metres or auto), tolerance — as the `deepsea bake` options
std::vector<Entry> read_manifest(const std::string& file, BakeFlags& flags) {
    YAML::Node root;
    try {
        root = YAML::LoadFile(file);
    } catch (const YAML::BadFile&) {
        throw IoError("cannot read manifest " + file);
    } catch (const YAML::Exception& e) {
        throw ConfigError(file + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
    }
    if (!root.IsMap()) throw ConfigError(file + ": not a manifest (expected cameras, rigs, waters)");
    const fs::path base = fs::path(file).parent_path();
    std::vector<std::string> lists[3];
    const char* names[3] = {"cameras", "rigs", "waters"};
    for (const auto& kv : root) {
        const std::string key = kv.first.as<std::string>();
        if (key == "bake") {
            if (!kv.second.IsMap() && !kv.second.IsNull()) fail(file, kv.second, key, "expected a map");
            for (const auto& b : kv.second) {
                const std::string k = b.first.as<std::string>();
                const std::string where = "bake." + k;
                try {
                    if (k == "xy_step") flags.settings.step = b.second.as<int>();
                    else if (k == "depth_samples") flags.settings.depth_samples = b.second.as<int>();
                    else if (k == "depth_scheme") flags.scheme = b.second.as<std::string>();
                    else if (k == "z_max") flags.z_max = b.second.as<std::string>();
                    else if (k == "tolerance") flags.settings.tolerance = b.second.as<double>();
                    else fail(file, b.first, where, "unknown key");
                } catch (const YAML::Exception&) {
                    fail(file, b.second, where, "wrong type");
                }
            }
            continue;
        }
        int which = -1;
        for (int i = 0; i < 3; ++i) if (key == names[i]) which = i;
        if (which < 0) fail(file, kv.first, key, "unknown key (cameras, rigs, waters, bake)");
        if (!kv.second.IsSequence() || kv.second.size() == 0) {
            fail(file, kv.second, key, "expected a non-empty list of files");
        }
        for (const auto& item : kv.second) {
            std::string s = item.as<std::string>();
            if (s.rfind("jerlov:", 0) != 0) {
                s = (base / s).string();
                if (!fs::exists(s)) fail(file, item, key, "missing file " + s);
            }
            lists[which].push_back(s);
        }
    }
    for (int i = 0; i < 3; ++i) {
        if (lists[i].empty()) throw ConfigError(file + ": missing key " + names[i]);
    }
    // Sorted and de-duplicated: the asset index (and so each shard's share) depends only on
    // the set of inputs, not on how the manifest happens to list them.
    for (auto& list : lists) {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    std::vector<Entry> out;
    for (const auto& c : lists[0]) {
        for (const auto& r : lists[1]) {
            for (const auto& w : lists[2]) {
                out.push_back({c, r, w, stem(c) + "__" + stem(r) + "__" + stem(w) + ".vdb"});
            }
        }
    }
    // Two inputs with one stem (cameras/a.yaml and other/a.yaml, or jerlov:IB and
    // jerlov-IB.yaml) would overwrite each other's asset: refuse rather than guess.
    std::vector<std::string> asset_names;
    for (const Entry& e : out) asset_names.push_back(e.name);
    std::sort(asset_names.begin(), asset_names.end());
    const auto dup = std::adjacent_find(asset_names.begin(), asset_names.end());
    if (dup != asset_names.end()) {
        throw ConfigError(file + ": two entries would both write " + *dup +
                          " (inputs with the same file stem)");
    }
    return out;
}

/// (index, count) of this shard: --shard i/n, else SLURM_ARRAY_TASK_ID/_COUNT (minus
/// SLURM_ARRAY_TASK_MIN), else JOB_COMPLETION_INDEX with --shard-count, else (0, 1).
std::pair<int, int> shard_of(const std::string& flag, int k8s_count) {
    auto parse_int = [](const char* s, const char* what) {
        char* end = nullptr;
        const long v = std::strtol(s, &end, 10);
        if (!*s || *end) throw ConfigError(std::string(what) + ": not an integer: '" + s + "'");
        return int(v);
    };
    int i = 0, n = 1;
    if (!flag.empty()) {
        const auto slash = flag.find('/');
        if (slash == std::string::npos) throw ConfigError("--shard: expected i/n, got '" + flag + "'");
        i = parse_int(flag.substr(0, slash).c_str(), "--shard");
        n = parse_int(flag.substr(slash + 1).c_str(), "--shard");
    } else if (const char* id = std::getenv("SLURM_ARRAY_TASK_ID")) {
        const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
        if (!count) throw ConfigError("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not");
        const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
        i = parse_int(id, "SLURM_ARRAY_TASK_ID") - (min ? parse_int(min, "SLURM_ARRAY_TASK_MIN") : 0);
        n = parse_int(count, "SLURM_ARRAY_TASK_COUNT");
    } else if (const char* idx = std::getenv("JOB_COMPLETION_INDEX")) {
        if (k8s_count < 1) throw ConfigError("JOB_COMPLETION_INDEX is set: give --shard-count N");
        i = parse_int(idx, "JOB_COMPLETION_INDEX");
        n = k8s_count;
    }
    if (n < 1 || i < 0 || i >= n) {
        throw ConfigError("shard " + std::to_string(i) + "/" + std::to_string(n) +
                          ": need 0 <= i < n");
    }
    return {i, n};
}

struct LibraryArgs {
    std::string manifest, out = "volumes/baked", shard;
    int shard_count = 0;
    bool force = false, dry_run = false;
};

void run(const LibraryArgs& a) {
    BakeFlags flags;
    const std::vector<Entry> entries = read_manifest(a.manifest, flags);
    BakeSettings settings;
    try {
        settings = flags.resolve();
    } catch (const ConfigError& e) {
        throw ConfigError(a.manifest + ": bake: " + e.what());  // name the file, not a flag
    }
    const auto [index, count] = shard_of(a.shard, a.shard_count);
    std::error_code ec;
    fs::create_directories(a.out, ec);
    if (ec) throw IoError("cannot create " + a.out + ": " + ec.message());

    int baked = 0, skipped = 0, failed = 0, mine = 0;
    for (std::size_t e = 0; e < entries.size(); ++e) {
        if (int(e % count) != index) continue;
        ++mine;
        const Entry& entry = entries[e];
        const std::string path = (fs::path(a.out) / entry.name).string();
        try {
            Setup setup = load_setup({entry.camera, entry.rig});
            setup.water = load_water(entry.water);
            require_complete(setup, entry.name);
            const BakeInfo want = bake_request(*setup.camera, *setup.rig, *setup.water, settings);
            if (!a.force && fs::exists(path)) {
                try {
                    if (read_asset_summary(path).info.input_hash == want.input_hash) {
                        std::printf("up to date  %s\n", path.c_str());
                        ++skipped;
                        continue;
                    }
                } catch (const Error&) {
                    // unreadable: bake it again
                }
            }
            if (a.dry_run) {
                std::printf("would bake  %s\n", path.c_str());
                continue;
            }
            const Asset asset = bake(*setup.camera, *setup.rig, *setup.water, settings);
            write_asset(path, asset);
            std::printf("baked       %s\n", path.c_str());
            ++baked;
        } catch (const Error& err) {
            std::fprintf(stderr, "deepsea: error: %s: %s\n", entry.name.c_str(), err.what());
            ++failed;
        }
    }
    std::printf("shard %d/%d: %d of %zu assets; baked %d, up to date %d, failed %d\n", index, count,
                mine, entries.size(), baked, skipped, failed);
    if (failed) throw FramesFailed(std::to_string(failed) + " asset(s) failed (listed above)");
}

}  // namespace

void setup_bake_library(CLI::App& sub) {
    auto a = std::make_shared<LibraryArgs>();
    sub.add_option("manifest", a->manifest, "library manifest (volumes/library.yaml)")->required();
    sub.add_option("--out", a->out, "folder for the assets");
    sub.add_option("--shard", a->shard, "i/n: bake only assets with index % n == i (0-based)");
    sub.add_option("--shard-count", a->shard_count, "shards when JOB_COMPLETION_INDEX is used");
    sub.add_flag("--force", a->force, "bake even if an asset is up to date");
    sub.add_flag("--dry-run", a->dry_run, "list what would be baked");
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
