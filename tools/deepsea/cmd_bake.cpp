// deepsea bake: one camera x rig x water asset, written atomically as .vdb.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/bake/accuracy.h"
#include "deepsea/bake/bake.h"
#include "deepsea/bake/lattice_rule.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"

namespace deepsea::cli {

namespace {

struct BakeArgs {
    SetupFlags setup;
    BakeFlags bake;
    std::string output;
    bool check = false, no_preview = false, full_float = false;
    int check_stride = 7;
};

void run(const BakeArgs& a) {
    BakeSettings settings = a.bake.resolve();
    require_writable(a.output);  // fail before a long bake, not after
    require_distinct(a.output, a.setup.inputs());
    Setup setup = a.setup.load();
    require_complete(setup, "deepsea bake");
    settings.port = setup.port;  // the columns follow its water-side rays (docs/ports.md)
    Progress bar("bake", 1);
    const auto t0 = std::chrono::steady_clock::now();
    const StopOnSignals stop;
    const auto stopped = [&] {
        return Cancelled("stopped by signal " + std::to_string(stop_signal()) + " before writing " +
                         a.output + "; nothing was written");
    };
    const Asset asset = [&] {
        try {
            return bake(*setup.camera, *setup.rig, *setup.water, settings,
                        a.bake.parallel([&](long done, long total) {
                            bar.set_total(total);
                            bar.update(done);
                            return stop_signal() == 0;
                        }));
        } catch (const Cancelled&) {
            throw stopped();
        }
    }();
    // A signal after the last poll (the stages between parallel loops): still nothing written.
    if (stop_signal() != 0) throw stopped();
    bar.finish();
    const double bake_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    WriteOptions w;
    w.preview = !a.no_preview;
    w.half = !a.full_float;
    write_asset(a.output, asset, w);
    const double total_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Lattice& l = asset.lattice();
    say("wrote %s: %dx%d columns (step %d) x %d samples (%s, z_max %.3f m), %.2f MB; "
        "bake %.2f s, with writing %.2f s\n",
        a.output.c_str(), l.ni, l.nj, l.step, l.nk(), to_string(l.scheme), l.z_max(),
        std::filesystem::file_size(a.output) / 1e6, bake_s, total_s);
    const std::string check = describe_check(asset.info);
    say("check: %s\n", check.c_str());
    if (asset.info.check.done && !meets_bar(asset.info.check)) {
        // Loud but not fatal: the asset is usable, the user decides (--strict-check to fail).
        std::fflush(stdout);
        std::fprintf(stderr, "warning: %s: the bake's check %s\n", a.output.c_str(), check.c_str());
    }
    if (asset.info.scattering == Scattering::Multiple) {
        const HigherOrderSettings& h = asset.info.higher_orders;
        say("multiple scattering: orders >= 2 are %.1f %% of the light at z_max, "
            "Monte Carlo standard error %.2f %% of the total (%d paths per column)\n",
            100.0 * h.fraction, 100.0 * h.rel_std_error, h.paths);
        say("multiple scattering: columns %.2f deg apart (every %d-th lattice column)",
            h.spacing_rad * 57.29577951308232, h.stride);
        if (h.check.done) {
            say("; check mean %.2f %%, max %.2f %% of the total at pixel (%g, %g) on %ld "
                "columns between them (their standard error %.2f %%)",
                100.0 * h.check.mean_rel, 100.0 * h.check.max_rel, h.check.max_u, h.check.max_v,
                h.check.columns, 100.0 * h.check.rel_std_error);
        }
        say("\n");
    }
    if (a.check) {  // asked for: printed with -q too
        // The file's values, as the runtime will see them (half storage included).
        const Asset loaded = load_asset(a.output);
        std::printf("%-22s %8s %12s %12s %8s\n", "scene", "z (m)", "mean rel", "max rel", "pixels");
        AccuracyOptions opt;
        opt.stride = a.check_stride;
        LatticeCheck full;
        full.done = true;
        const std::vector<AccuracyRow> rows = [&] {
            try {
                return evaluate_asset_accuracy(loaded, opt, a.bake.parallel());
            } catch (const Cancelled&) {
                throw Cancelled("stopped by signal " + std::to_string(stop_signal()) +
                                " during --check; " + a.output + " was written and is complete");
            }
        }();
        for (const AccuracyRow& r : rows) {
            std::printf("%-22s %8.3f %11.4f%% %11.4f%% %8ld\n", r.scene.c_str(), r.z,
                        100.0 * r.mean_rel, 100.0 * r.max_rel, r.pixels);
            full.mean_rel = std::max(full.mean_rel, r.mean_rel);
            full.max_rel = std::max(full.max_rel, r.max_rel);
        }
        if (loaded.info.scattering == Scattering::Multiple) {
            // The exact reference is single scattering: orders >= 2 show up as error here.
            std::printf(
                "full check: no verdict for a multiple-scattering asset (the exact reference "
                "is single scattering; the bake's own check ran before orders >= 2)\n");
            return;
        }
        std::printf("full check: %s the bar (%.2f %% mean / %.0f %% max)\n",
                    meets_bar(full) ? "meets" : "MISSES", 100.0 * kBarMeanRel, 100.0 * kBarMaxRel);
        if (settings.strict && !meets_bar(full)) {
            std::error_code ec;
            std::filesystem::remove(a.output, ec);  // a strict check leaves no failed asset
            throw AccuracyError(a.output + ": full check misses the bar: mean " +
                                std::to_string(100.0 * full.mean_rel) + " %, max " +
                                std::to_string(100.0 * full.max_rel) +
                                " % (removed; give a finer --xy-step or --depth-samples)");
        }
    }
}

}  // namespace

void setup_bake(CLI::App& sub) {
    auto a = std::make_shared<BakeArgs>();
    a->setup.add_to(sub);
    a->bake.add_to(sub);
    sub.add_option("-o,--output", a->output, "asset to write (.vdb)")->required();
    sub.add_flag("--check", a->check,
                 "compare the written asset with exact per-pixel integration on a full grid "
                 "of test pixels (the bake's own check samples fewer)");
    sub.add_option("--check-stride", a->check_stride, "--check: test every n-th pixel")
        ->check(CLI::PositiveNumber);
    sub.add_flag("--no-preview", a->no_preview, "leave out the density/color preview grids");
    sub.add_flag("--full-float", a->full_float, "store 32-bit floats instead of half");
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
