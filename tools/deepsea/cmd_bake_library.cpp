// deepsea bake-library: bake every camera x rig x water of a manifest, skipping assets whose
// inputs are unchanged; shardable so that array jobs split a large library without overlap.

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/library_manifest.h"

namespace deepsea::cli {

namespace {

namespace fs = std::filesystem;

/// (index, count) of this shard: --shard i/n, else SLURM_ARRAY_TASK_ID/_COUNT (minus
/// SLURM_ARRAY_TASK_MIN), else JOB_COMPLETION_INDEX with --shard-count, else (0, 1).
/// `given`: --shard was on the command line, even as '' (an unset shell variable), which is a
/// usage error, not "no shard": it used to bake the whole library on every array task.
std::pair<int, int> shard_of(const std::string& flag, bool given, int k8s_count) {
    auto parse_int = [](const char* s, const char* what) {
        char* end = nullptr;
        errno = 0;
        const long v = std::strtol(s, &end, 10);
        if (!*s || *end || std::isspace(static_cast<unsigned char>(*s)) || errno == ERANGE ||
            v < INT_MIN || v > INT_MAX)
            throw ConfigError(std::string(what) + ": not an integer: '" + s + "'");
        return int(v);
    };
    int i = 0, n = 1;
    if (given && flag.empty())
        throw ConfigError("--shard: expected i/n (e.g. 0/4), got '' (an unset variable?)");
    if (given) {
        const auto slash = flag.find('/');
        if (slash == std::string::npos)
            throw ConfigError("--shard: expected i/n, got '" + flag + "'");
        i = parse_int(flag.substr(0, slash).c_str(), "--shard");
        n = parse_int(flag.substr(slash + 1).c_str(), "--shard");
    } else if (const char* id = std::getenv("SLURM_ARRAY_TASK_ID")) {
        const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
        if (!count)
            throw ConfigError("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not");
        const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
        i = parse_int(id, "SLURM_ARRAY_TASK_ID") -
            (min ? parse_int(min, "SLURM_ARRAY_TASK_MIN") : 0);
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
    bool shard_given = false;  ///< --shard on the command line, even empty
    int shard_count = 0;
    bool force = false, dry_run = false;
    int threads = 0;
};

void run(const LibraryArgs& a) {
    const LibraryManifest manifest = load_library_manifest(a.manifest);
    const std::vector<LibraryEntry>& entries = manifest.entries;
    BakeFlags flags;
    const LibraryBakeSettings& b = manifest.bake;
    if (b.xy_step) flags.settings.step = *b.xy_step;
    if (b.depth_samples) flags.settings.depth_samples = *b.depth_samples;
    if (b.depth_scheme) flags.scheme = *b.depth_scheme;
    if (b.z_max) flags.z_max = *b.z_max;
    if (b.tolerance) flags.settings.tolerance = *b.tolerance;
    if (b.scattering) flags.scattering = *b.scattering;
    if (b.paths) flags.settings.higher_orders.paths = *b.paths;
    flags.threads = a.threads;
    BakeSettings settings;
    try {
        settings = flags.resolve();
    } catch (const ConfigError& e) {
        throw ConfigError(a.manifest + ": bake: " + e.what());  // name the file, not a flag
    }
    // Read every input once before baking anything: a config error (a value out of range, a
    // lamp in the camera's near field) stops the whole run with exit 2, as a missing file does,
    // instead of failing its assets one by one after others have been baked.
    for (const std::string& f : manifest.cameras) load_setup({f});
    for (const std::string& f : manifest.rigs) load_setup({f});
    for (const std::string& w : manifest.waters) load_water(w);
    const auto [index, count] = shard_of(a.shard, a.shard_given, a.shard_count);
    std::error_code ec;
    fs::create_directories(a.out, ec);
    if (ec) throw IoError("cannot create " + a.out + ": " + ec.message());

    int baked = 0, skipped = 0, failed = 0, mine = 0;
    // A signal stops the asset being baked (nothing of it is written) and the run; assets
    // written are complete, and running the same command again bakes only what is missing.
    const StopOnSignals stop;
    const Parallel par = flags.parallel([](long, long) { return stop_signal() == 0; });
    const auto stopped = [&](const std::string& name) {
        return Cancelled("stopped by signal " + std::to_string(stop_signal()) + " at " + name +
                         " after baking " + std::to_string(baked) +
                         " asset(s); every asset written is complete; run the same command "
                         "again to finish");
    };
    for (std::size_t e = 0; e < entries.size(); ++e) {
        if (int(e % count) != index) continue;
        if (stop_signal() != 0) throw stopped(entries[e].name);
        ++mine;
        const LibraryEntry& entry = entries[e];
        const std::string path = (fs::path(a.out) / entry.name).string();
        try {
            Setup setup = load_setup({entry.camera, entry.rig});
            setup.water = load_water(entry.water);
            require_complete(setup, entry.name);
            const BakeInfo want = bake_request(*setup.camera, *setup.rig, *setup.water, settings);
            // An asset of an older format, or unreadable, is baked again.
            if (!a.force && asset_up_to_date(path, want.input_hash)) {
                std::printf("up to date  %s\n", path.c_str());
                ++skipped;
                continue;
            }
            if (a.dry_run) {
                std::printf("would bake  %s\n", path.c_str());
                continue;
            }
            const Asset asset = bake(*setup.camera, *setup.rig, *setup.water, settings, par);
            write_asset(path, asset);
            std::printf("baked       %s\n", path.c_str());
            std::fflush(stdout);
            ++baked;
        } catch (const Cancelled&) {
            throw stopped(entry.name);
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
    CLI::Option* shard = sub.add_option(
        "--shard", a->shard, "i/n: bake only assets with index % n == i (0-based); not empty");
    sub.add_option("--shard-count", a->shard_count, "shards when JOB_COMPLETION_INDEX is used");
    sub.add_flag("--force", a->force, "bake even if an asset is up to date");
    sub.add_flag("--dry-run", a->dry_run, "list what would be baked");
    add_threads(sub, a->threads);
    sub.callback([a, shard] {
        a->shard_given = shard->count() > 0;
        run(*a);
    });
}

}  // namespace deepsea::cli
