// deepsea render: composite one frame or a whole sequence with a baked asset.

#include <cstdio>
#include <optional>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/batch/frame_poses.h"
#include "deepsea/batch/layer_files.h"
#include "deepsea/batch/output_folders.h"
#include "deepsea/batch/sequence.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/image_io.h"
#include "deepsea/io/poses.h"

namespace deepsea::cli {

namespace {

struct RenderArgs {
    DepthFlags depth;
    std::string asset, rgb, depth_path, output, layers, exposure, camera, poses;
    std::string layer_set = "all", format;
    bool resume = false, no_forward = false, half = false, shadows = false, streaks = false;
    std::string snow;  ///< empty: not given (the --camera file's snow section, else none)
    std::uint64_t snow_seed = 1;
    int bits = 8;
    int threads = 0;
    int shadow_step = kDefaultShadowStep;
    const CLI::Option* shadow_step_option = nullptr;  ///< whether --shadow-step was given
    ShardFlags shard;
};

/// --shard: this shard's part of the sequence `jobs` (contiguous, in frame order, sizes
/// differing by one at most), recorded in `opt`; a shard's auto exposure is chosen on the
/// sequence's first frame, as an unsharded run's is.
std::vector<FrameJob> shard_jobs(const std::vector<FrameJob>& jobs, const FrameFiles& files,
                                 std::pair<int, int> shard, SequenceOptions& opt) {
    const auto [i, n] = shard;
    if (!files.sequence())
        throw ConfigError("--shard splits a sequence, and --rgb is one file: give a pattern");
    if (opt.camera_model && opt.camera_model->auto_exposure.enabled)
        throw ConfigError(
            "--shard: the camera's auto_exposure controller sets each frame's "
            "exposure from the frames before it, so a shard cannot start "
            "mid-sequence; render unsharded or turn the controller off");
    const long total = long(jobs.size());
    if (n > total)
        throw ConfigError("--shard " + std::to_string(i) + "/" + std::to_string(n) +
                          ": the "
                          "sequence has " +
                          std::to_string(total) + " frame(s); give at most " +
                          std::to_string(total) + " shards");
    const auto folder = [](const std::string& dir) {
        return dir.empty() ? dir : resolved_path(dir).string();
    };
    opt.shard = ShardRecord{i, n, int(total), folder(files.output), folder(files.layers)};
    if (!opt.camera_model && opt.exposure.automatic) opt.exposure_frame = jobs.front();
    return {jobs.begin() + total * i / n, jobs.begin() + total * (i + 1) / n};
}

void run(const RenderArgs& a) {
    SequenceOptions opt;
    opt.exposure = parse_exposure(a.exposure.empty() ? "auto" : a.exposure);
    opt.depth_read = a.depth.read_options();
    opt.depth_kind = a.depth.depth_kind();
    opt.resume = a.resume;
    opt.forward = !a.no_forward;
    opt.shadows = a.shadows;
    if (a.shadow_step_option && a.shadow_step_option->count() > 0) {
        if (!a.shadows)
            throw ConfigError("--shadow-step sets how lamp shadows are swept: give --shadows");
        if (a.shadow_step < 1 || a.shadow_step > kMaxShadowStep)
            throw ConfigError("--shadow-step: must be from 1 (every pixel) to " +
                              std::to_string(kMaxShadowStep) + " pixels, got " +
                              std::to_string(a.shadow_step));
        opt.shadow_step = a.shadow_step;
    }
    opt.bits = a.bits;
    if ((a.half || a.layer_set != "all") && a.layers.empty())
        throw ConfigError("--layer-set and --half choose what --layers writes: give --layers");
    opt.version = DEEPSEA_VERSION;
    std::optional<Snow> setup_snow;
    if (!a.camera.empty()) {
        Setup s = load_setup({a.camera});
        setup_snow = s.snow;
        if (!s.camera) throw ConfigError(a.camera + ": no camera section");
        opt.camera = *s.camera;
        opt.camera_model = s.camera_model;
        opt.port = s.port;  // rendered through (docs/ports.md)
    }
    if (opt.camera_model && !a.exposure.empty())
        throw ConfigError("--exposure: " + a.camera +
                          " records the frames with a camera (lens, sensor, processing), whose "
                          "exposure is camera.sensor's exposure_time_ms and gain");
    opt.snow = snow_settings(a.snow, a.snow_seed, opt.camera_model, setup_snow);
    if (a.streaks) {
        if (!opt.snow) throw ConfigError("--snow-streaks: no marine snow to streak; give --snow");
        opt.snow->streaks = true;
    }
    if (opt.snow && opt.port)
        throw ConfigError(
            "--snow: marine snow through a port is not built yet (particles are "
            "drawn in the input's pinhole pixels; docs/ports.md)");
    opt.layer_output.camera = opt.camera_model.has_value();
    opt.layer_output.names = parse_layer_set(a.layer_set, opt.layer_output.camera);
    opt.layer_output.half = a.half;
    // Everything that can be checked without rendering is checked before the asset is loaded
    // and before any folder is made.
    const FrameFiles files{a.rgb, a.depth_path, a.output, a.layers, a.format};
    std::vector<FrameJob> jobs = frame_jobs(files);
    // By timestamp where the frames are named by their time, else the n-th pose to the n-th
    // frame; with streaks, each frame's shutter (docs/snow-shadows.md, "Motion streaks").
    if (!a.poses.empty()) assign_poses(jobs, load_tum_poses(a.poses), a.poses, opt.snow);
    if (const auto shard = a.shard.resolve(false)) jobs = shard_jobs(jobs, files, *shard, opt);
    if (a.bits == 16 && !jobs.empty() && image_format(jobs.front().output) == "jpg")
        throw ConfigError("--bits 16: JPEG holds 8 bits per sample; write PNG or TIFF for 16");
    const Asset asset = load_asset(a.asset);
    std::optional<OutputFolders> folders;
    if (files.sequence()) {
        folders.emplace(files, jobs, opt.shard);
        opt.manifests = folders->manifests();
        opt.rgb_pattern = a.rgb;
        opt.depth_pattern = a.depth_path;
    }
    Progress bar("render", long(jobs.size()));
    opt.on_frame = frame_lines();
    opt.progress = [&](long done, long) {
        bar.update(done);
        return stop_signal() == 0;
    };
    SequenceResult r;
    {
        const StopOnSignals stop;
        in_arena(a.threads, [&] { r = render_sequence(asset, jobs, opt); });
    }
    bar.finish();
    // One frame that failed: its error is the one line (main prints it), with its own exit code
    // (4 for a missing file, 3 for sizes that differ, as `reference`), no summary.
    if (jobs.size() == 1 && !r.errors.empty()) throw_error(r.error_codes.front(), r.errors.front());
    for (const std::string& e : r.errors) std::fprintf(stderr, "deepsea: error: %s\n", e.c_str());
    if (folders && folders->stale_removed() > 0) {
        say("removed %d stale temporary file(s) of an interrupted run\n", folders->stale_removed());
    }
    if (opt.shard) say("shard %d/%d: ", opt.shard->index, opt.shard->count);
    if (opt.camera_model) {
        say("rendered %d frame(s), skipped %d, failed %zu in %.2f s (camera: %.6g ms, "
            "%.6g DN/e-)\n",
            r.written, r.skipped, r.errors.size(), r.seconds, r.camera_exposure.exposure_time_ms,
            r.camera_exposure.system_gain);
    } else {
        say("rendered %d frame(s), skipped %d, failed %zu in %.2f s (exposure %.6g)\n", r.written,
            r.skipped, r.errors.size(), r.seconds, r.exposure);
    }
    if (r.interrupted) {
        const int left = r.total - r.written - r.skipped - int(r.errors.size());
        throw Cancelled("stopped by signal " + std::to_string(stop_signal()) + " with " +
                        std::to_string(left) + " of " + std::to_string(r.total) +
                        " frame(s) not rendered; every output written is complete; run the "
                        "same command with --resume to finish");
    }
    if (jobs.size() == 1 && r.written == 1) {
        if (!a.output.empty()) say("wrote %s\n", a.output.c_str());
        if (!a.layers.empty()) say("wrote %s\n", a.layers.c_str());
    } else if (!a.output.empty() && r.written > 0) {
        say("wrote frames to %s\n", a.output.c_str());
    }
    if (!r.errors.empty()) throw FramesFailed("some frames failed (listed above)");
}

}  // namespace

void setup_render(CLI::App& sub) {
    auto a = std::make_shared<RenderArgs>();
    a->depth.add_to(sub);
    sub.add_option("--asset", a->asset, "baked asset (.vdb) for the rig, water and camera")
        ->required();
    sub.add_option("--rgb", a->rgb, "colour image, or a quoted glob such as 'dir/*.png'")
        ->required();
    sub.add_option("--depth", a->depth_path,
                   "depth image, or a quoted glob such as 'dir/*_depth.exr' (frames pair by "
                   "file name or frame number)")
        ->required();
    sub.add_option("-o,--output", a->output, "exposed image; a folder for a sequence");
    sub.add_option("--layers", a->layers, "multi-layer EXR; a folder for a sequence");
    // Checked while parsing: a misspelt layer is a usage error (exit 2), before any work.
    const CLI::Validator layer_names(
        [](std::string& text) -> std::string {
            try {
                (void)parse_layer_set(text, true);  // camera layers: checked once --camera is read
            } catch (const Error& e) {
                const std::string m = e.what(), prefix = "--layer-set: ";  // CLI11 names it
                return m.rfind(prefix, 0) == 0 ? m.substr(prefix.size()) : m;
            }
            return "";
        },
        "");
    sub.add_option("--layer-set", a->layer_set,
                   "layers the --layers files hold, comma-separated: final, direct, forward, "
                   "backscatter, transmission, depth, normal, with --snow snow, snow_id, with a "
                   "camera stage raw, "
                   "linear_dn, noise_free, or all")
        ->check(layer_names);
    sub.add_flag("--half", a->half, "write the --layers files in half floats (16 bits)");
    sub.add_option("--exposure", a->exposure,
                   "'auto' (the default: first frame's, then kept, in the sequence manifest) or "
                   "a factor; not with a camera stage")
        ->default_str("auto");
    sub.add_option("--camera", a->camera,
                   "YAML with the frames' camera (default: the asset's); with lens, sensor or "
                   "processing keys, a camera stage records each frame (docs/camera.md)");
    sub.add_option("--format", a->format,
                   "a sequence's image format (default png); one frame: -o's extension")
        ->check(CLI::IsMember({"png", "jpg", "tif", "exr"}));
    sub.add_option("--bits", a->bits, "PNG/TIFF bit depth")->check(CLI::IsMember({8, 16}));
    sub.add_flag("--resume", a->resume,
                 "continue a sequence: skip frames whose outputs are complete, keep the "
                 "exposure of deepsea-sequence.json, refuse other settings");
    sub.add_flag("--no-forward", a->no_forward, "leave forward scatter out");
    a->shard.add_to(sub,
                    "render only part i of n of a sequence (0-based; contiguous frames), with "
                    "its own manifest; `deepsea merge-shards` checks and joins the parts");
    sub.add_flag(
        "--shadows", a->shadows,
        "lamp shadows from the depth map, penumbrae from each lamp's radius "
        "(docs/snow-shadows.md, \"Lamp shadows\"); off by default, as in the paper's model");
    a->shadow_step_option =
        sub.add_option("--shadow-step", a->shadow_step,
                       "with --shadows: pixels between the swept samples along each axis, 1 (every "
                       "pixel, the reference) to 8; default 2 (docs/snow-shadows.md, \"Reduced "
                       "resolution\")")
            ->default_str(std::to_string(kDefaultShadowStep));
    sub.add_option(
        "--snow", a->snow,
        "marine snow lit by the lamps (docs/snow-shadows.md, \"Marine snow\"): a preset, "
        "abyssal, nepheloid or plume, or off; overrides the --camera file's snow "
        "section (docs/config.md), which applies without it; adds the layers snow "
        "and snow_id");
    sub.add_option("--poses", a->poses,
                   "TUM trajectory file (timestamp tx ty tz qx qy qz qw a line, camera to "
                   "world; # comments), so that marine snow stays fixed in the world: frames named "
                   "by their timestamps (1305031102.175304.png) take the pose at their time, "
                   "others the n-th pose the n-th frame; snow.streaks draws motion streaks "
                   "(docs/snow-shadows.md, \"Marine snow\", \"Motion streaks\")");
    sub.add_flag("--snow-streaks", a->streaks,
                 "marine snow drawn as motion streaks from the --poses and the exposure time "
                 "(as the snow section's streaks: true; docs/snow-shadows.md, \"Motion "
                 "streaks\")");
    sub.add_option("--snow-seed", a->snow_seed,
                   "seed of the marine snow's particles (same seed, same particles)")
        ->default_str("1");
    add_threads(sub, a->threads);
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
