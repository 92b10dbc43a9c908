// deepsea bake-library: bake every camera x rig x water of a manifest, skipping assets whose
// inputs are unchanged; shardable so that array jobs split a large library without overlap.

#include <algorithm>
#include <cstdio>
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

struct LibraryArgs {
    std::string manifest, out = "volumes/baked";
    ShardFlags shard;
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
    const auto [index, count] = *a.shard.resolve(true);
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
            settings.port = setup.port;  // the entry's camera's port, or none
            const BakeInfo want = bake_request(*setup.camera, *setup.rig, *setup.water, settings);
            // An asset of an older format, or unreadable, is baked again.
            if (!a.force && asset_up_to_date(path, want.input_hash)) {
                say("up to date  %s\n", path.c_str());
                ++skipped;
                continue;
            }
            if (a.dry_run) {
                say("would bake  %s\n", path.c_str());
                continue;
            }
            const Asset asset = bake(*setup.camera, *setup.rig, *setup.water, settings, par);
            write_asset(path, asset);
            say("baked       %s\n", path.c_str());
            std::fflush(stdout);
            ++baked;
        } catch (const Cancelled&) {
            throw stopped(entry.name);
        } catch (const Error& err) {
            std::fprintf(stderr, "deepsea: error: %s: %s\n", entry.name.c_str(), err.what());
            ++failed;
        }
    }
    say("shard %d/%d: %d of %zu assets; baked %d, up to date %d, failed %d\n", index, count, mine,
        entries.size(), baked, skipped, failed);
    if (failed) throw FramesFailed(std::to_string(failed) + " asset(s) failed (listed above)");
}

}  // namespace

void setup_bake_library(CLI::App& sub) {
    auto a = std::make_shared<LibraryArgs>();
    sub.add_option("manifest", a->manifest, "library manifest (volumes/library.yaml)")->required();
    sub.add_option("--out", a->out, "folder for the assets");
    a->shard.add_to(sub, "bake only assets with index % n == i (0-based)");
    sub.add_flag("--force", a->force, "bake even if an asset is up to date");
    sub.add_flag("--dry-run", a->dry_run, "list what would be baked");
    add_threads(sub, a->threads);
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
