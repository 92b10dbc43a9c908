// deepsea bench: times the compositor alone (no file I/O) on generated frames, each stage of a
// frame's conversion on its own (decode, composite, encode), the camera stage on a rendered
// frame's radiance, and whole sequences from files to files. Medians over repeated runs; peak
// memory from /proc (VmHWM); CPU time from getrusage.

#include <malloc.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <optional>
#include <utility>

#include "bench.h"
#include "cli_util.h"
#include "commands.h"
#include "deepsea/bake/bake.h"
#include "deepsea/batch/sequence.h"
#include "deepsea/camera/camera_stage.h"
#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/jerlov.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/lamp_shadows.h"
#include "deepsea/runtime/renderer.h"
#include "deepsea/scene/flight.h"

namespace deepsea::cli {

namespace {

namespace fs = std::filesystem;

using namespace bench;  // NOLINT: the cases and their clocks (bench.h)

/// A temporary folder for generated files, removed with everything in it at the end.
struct TempFolder {
    fs::path dir;
    explicit TempFolder(const std::string& tag)
        : dir(fs::temp_directory_path() /
              ("deepsea-bench-" + tag + "-" + std::to_string(getpid()))) {
        fs::create_directories(dir);
    }
    ~TempFolder() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;
};

/// Each stage of one frame's conversion timed on its own, one thread pool as in a render:
/// decoding the colour PNG (with the sRGB decode to linear float), decoding the depth EXR,
/// compositing the image only, and encoding the exposed image to PNG and to JPEG (with the
/// sRGB encode, written to disk).
std::vector<Case> time_stages(const Asset& asset, const Camera& cam, const BenchArgs& a,
                              int threads) {
    FlightParams flight;
    flight.camera = cam;
    Frame frame = render_flight_frame(flight, 0);
    const TempFolder tmp("stages");
    const std::string png = (tmp.dir / "f.png").string(), exr = (tmp.dir / "f_depth.exr").string();
    write_color(png, frame.rgb);
    write_depth_exr(exr, frame.depth);
    RenderSettings settings;
    settings.camera = cam;
    Renderer renderer(asset, settings);
    Layers layers;
    renderer.render(layers, frame, LayerSet::Final);
    const double factor = exposure_factor(Exposure{}, layers.final);
    const Image exposed = apply_exposure(layers.final, factor);
    const auto time = [&](const std::string& name, const std::function<void()>& f) {
        f();  // first call allocates, loads codecs
        std::vector<double> t, cpu;
        for (int r = 0; r < a.repeats; ++r) {
            const double t0 = now_ms(), c0 = cpu_ms();
            f();
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
        }
        return summarize(name, cam.width, cam.height, threads, t, cpu);
    };
    std::vector<Case> cases;
    cases.push_back(time("stage-decode-color-png", [&] { (void)read_color(png); }));
    cases.push_back(time("stage-decode-depth-exr", [&] { (void)read_depth(exr); }));
    cases.push_back(
        time("stage-composite", [&] { renderer.render(layers, frame, LayerSet::Final); }));
    cases.push_back(time("stage-expose", [&] { (void)apply_exposure(layers.final, factor); }));
    cases.push_back(
        time("stage-encode-png", [&] { write_color((tmp.dir / "o.png").string(), exposed); }));
    cases.push_back(
        time("stage-encode-jpeg", [&] { write_color((tmp.dir / "o.jpg").string(), exposed); }));
    return cases;
}

/// The camera stage (docs/camera.md) on one rendered frame's radiance, one thread pool as in a
/// render: the default camera model with its exposure time set so that the radiance the
/// automatic exposure maps to white fills the full well in G; the image alone ("camera"),
/// every layer ("camera-layers"), the image as the 8-bit codes a PNG or JPEG render asks for
/// ("camera-codes"), and with a lens's barrel distortion ("camera-lens").
std::vector<Case> time_camera(const Asset& asset, const Camera& cam, const BenchArgs& a,
                              int threads) {
    if (!wanted(a.cases, "camera") && !wanted(a.cases, "camera-layers") &&
        !wanted(a.cases, "camera-codes") && !wanted(a.cases, "camera-lens"))
        return {};
    FlightParams flight;
    flight.camera = cam;
    Frame frame = render_flight_frame(flight, 0);
    RenderSettings settings;
    settings.camera = cam;
    Renderer renderer(asset, settings);
    Layers layers;
    renderer.render(layers, frame, LayerSet::Final);
    const double white = 1.0 / exposure_factor(Exposure{}, layers.final);
    std::vector<Case> cases;
    const auto time = [&](const std::string& name, CameraModel model, CameraLayerSet set) {
        const CameraStage probe(model, cam);
        model.sensor.exposure_time_ms = std::clamp(
            model.sensor.full_well / (white * probe.electrons_per_radiance(1, 1.0)), 1e-3, 3.6e6);
        const CameraStage stage(model, cam);
        CameraOutput out;
        std::uint64_t key = 0;
        stage.apply(out, layers.final, key++, set);  // allocates the outputs
        std::vector<double> t, cpu;
        for (int r = 0; r < a.repeats; ++r) {
            const double t0 = now_ms(), c0 = cpu_ms();
            stage.apply(out, layers.final, key++, set);
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
        }
        cases.push_back(summarize(name, cam.width, cam.height, threads, t, cpu));
    };
    if (wanted(a.cases, "camera")) time("camera", CameraModel{}, {});
    if (wanted(a.cases, "camera-layers"))
        time("camera-layers", CameraModel{}, CameraLayerSet::all());
    if (wanted(a.cases, "camera-codes")) {
        CameraLayerSet codes;
        codes.codes8 = true;
        time("camera-codes", CameraModel{}, codes);
    }
    if (wanted(a.cases, "camera-lens")) {
        CameraModel lens;
        lens.lens.distortion = {-0.12, 0.02, 0.0, 0.0, 0.0};
        time("camera-lens", lens, {});
    }
    return cases;
}

/// Whole sequences from files to files (PNG colour + EXR depth in, PNG or JPEG out), as
/// `deepsea render` runs them: `frames` file pairs (copies of two generated frames, so that the
/// bench does not spend minutes generating scenes), three runs, the median reported with the
/// frame rate and the CPU time per frame (user + system, all threads). The "-camera" cases
/// record the frames with the setup's camera stage (or the default camera model), as
/// `render --camera` does; the "-camera-snow-shadows" cases also cast lamp shadows and draw the
/// abyssal marine snow, as `deepsea demo` does. Beside the whole run's rate (its start included:
/// the compositor's making, the exposure, the pipeline's fill), the steady rate: wall and CPU time
/// from the kSteadyFrom-th frame written to the last (the drain included), over the frames in
/// between, as the sequence's progress reports them. A user's sequence of 10^4 frames runs at that
/// rate.
std::vector<Case> time_sequences(const Asset& asset, const Camera& cam, const BenchArgs& a,
                                 int threads, const std::optional<CameraModel>& model) {
    // The plain frame, with the camera stage, and as `deepsea demo` renders it: the camera
    // stage, lamp shadows and the demo's abyssal marine snow (drawn afresh per frame: no poses).
    const char* const formats[] = {"sequence-png", "sequence-jpeg"};
    const char* const variants[] = {"", "-camera", "-camera-snow-shadows"};
    bool any = false;  // (each case by its own name: sequence-jpeg-camera is no prefix of another)
    for (const char* f : formats)
        for (const char* v : variants) any = any || wanted(a.cases, std::string(f) + v);
    if (!any) return {};
    const TempFolder tmp("sequence");
    fs::create_directories(tmp.dir / "out");
    FlightParams flight;
    flight.camera = cam;
    constexpr int kFrames = 16, kGenerated = 2, kSteadyFrom = 4;
    for (int i = 0; i < kGenerated; ++i) {
        const Frame f = render_flight_frame(flight, i);
        write_color((tmp.dir / ("f" + std::to_string(i) + ".png")).string(), f.rgb);
        write_depth_exr((tmp.dir / ("f" + std::to_string(i) + "_depth.exr")).string(), f.depth);
    }
    std::vector<Case> cases;
    for (const char* format : formats) {
        const std::string ext = format == formats[0] ? ".png" : ".jpg";
        for (const char* variant : variants) {
            const std::string name = std::string(format) + variant;
            const bool camera = variant != variants[0], look = variant == variants[2];
            if (!wanted(a.cases, name)) continue;
            std::vector<FrameJob> jobs;
            for (int i = 0; i < kFrames; ++i) {
                const std::string g = std::to_string(i % kGenerated), k = std::to_string(i);
                const fs::path rgb = tmp.dir / ("in" + k + ".png"),
                               depth = tmp.dir / ("in" + k + ".exr");
                if (!fs::exists(rgb)) fs::copy_file(tmp.dir / ("f" + g + ".png"), rgb);
                if (!fs::exists(depth)) fs::copy_file(tmp.dir / ("f" + g + "_depth.exr"), depth);
                jobs.push_back({rgb.string(), depth.string(),
                                (tmp.dir / "out" / (k + ext)).string(), "", std::nullopt,
                                std::nullopt});
            }
            SequenceOptions opt;
            opt.forward = !a.no_forward;
            if (camera) {
                opt.camera_model = model ? *model : CameraModel{};
                opt.layer_output.camera = true;
            }
            if (look) {
                opt.shadows = true;
                opt.snow = cli::snow_settings("abyssal", 1, opt.camera_model);
            }
            double steady_wall0 = 0, steady_cpu0 = 0;
            opt.progress = [&](long done, long) {
                if (done == kSteadyFrom) {
                    steady_wall0 = now_ms();
                    steady_cpu0 = cpu_ms();
                }
                return true;
            };
            reset_peak_rss();
            std::vector<double> wall, cpu, steady_wall, steady_cpu;
            for (int r = 0; r < 3; ++r) {
                const double c0 = cpu_ms();
                const SequenceResult res = render_sequence(asset, jobs, opt);
                const double c1 = cpu_ms(), w1 = now_ms();
                cpu.push_back((c1 - c0) / kFrames);
                if (!res.errors.empty())
                    throw IoError("bench sequence failed: " + res.errors.front());
                wall.push_back(res.seconds * 1000.0 / kFrames);
                steady_wall.push_back((w1 - steady_wall0) / (kFrames - kSteadyFrom));
                steady_cpu.push_back((c1 - steady_cpu0) / (kFrames - kSteadyFrom));
            }
            Case c = summarize(name, cam.width, cam.height, threads, wall, cpu);
            c.cpu_ms_per_frame = c.median_cpu_ms;
            c.fps = 1000.0 / c.median_ms;
            const Case steady =
                summarize(name, cam.width, cam.height, threads, steady_wall, steady_cpu);
            c.steady_fps = 1000.0 / steady.median_ms;
            c.steady_cpu_ms_per_frame = steady.median_cpu_ms;
            cases.push_back(c);
        }
    }
    return cases;
}

void run(const BenchArgs& a) {
    if (a.repeats < 1) throw ConfigError("--repeats must be >= 1");
    // Resident memory before any work: mostly the shared libraries (OpenVDB, OpenEXR, TBB, the
    // C++ runtime; OpenImageIO's are loaded only if a case needs it), counted in every peak.
    const double baseline_mb = status_kb("VmRSS: %lf kB") / 1024.0;
    const int threads = a.threads > 0 ? a.threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Setup setup = load_setup({a.config});
    require_complete(setup, a.config);
    refuse_port(setup, a.config,
                "bench's cases are timed without a port and its own composite_flat_port case "
                "adds one");
    std::vector<Case> cases;
    for (const auto& [w, h] : {std::pair{800, 800}, std::pair{1920, 1080}}) {
        const Camera cam = scaled(*setup.camera, w, h);
        for (Case& c : time_shadows(cam, *setup.rig, a, threads)) cases.push_back(c);
        if (only_shadows(a.cases)) continue;
        // One bake per size for every case (the forward blur left out of the water with
        // --no-forward).
        Water water = *setup.water;
        if (a.no_forward) water.forward.enabled = false;
        const Asset asset = bake(cam, *setup.rig, water, bench_bake(a));
        if (wants_compositor(a.cases)) {
            for (Case& c : time_compositor(asset, cam, a, threads)) cases.push_back(c);
        }
        if (wanted(a.cases, "stage")) {
            for (Case& c : time_stages(asset, cam, a, threads)) cases.push_back(c);
        }
        for (Case& c : time_snow(asset, cam, a, threads)) cases.push_back(c);
        for (Case& c : time_camera(asset, cam, a, threads)) cases.push_back(c);
        for (Case& c : time_sequences(asset, cam, a, threads, setup.camera_model))
            cases.push_back(c);
    }
    if (a.json) {
        std::printf("{\"baseline_rss_mb\": %.1f, \"scattering\": \"%s\", \"cases\": [", baseline_mb,
                    a.scattering.c_str());
        for (std::size_t i = 0; i < cases.size(); ++i) {
            const Case& c = cases[i];
            std::printf(
                "%s{\"name\": \"%s\", \"width\": %d, \"height\": %d, \"threads\": %d, "
                "\"runs\": %d, \"median_ms\": %.3f, \"min_ms\": %.3f, \"max_ms\": %.3f, "
                "\"median_cpu_ms\": %.3f, \"peak_rss_mb\": %.1f",
                i ? ", " : "", c.name.c_str(), c.width, c.height, c.threads, c.runs, c.median_ms,
                c.min_ms, c.max_ms, c.median_cpu_ms, c.peak_rss_mb);
            if (c.fps > 0) {
                std::printf(
                    ", \"fps\": %.2f, \"cpu_ms_per_frame\": %.2f, \"steady_fps\": %.2f, "
                    "\"steady_cpu_ms_per_frame\": %.2f",
                    c.fps, c.cpu_ms_per_frame, c.steady_fps, c.steady_cpu_ms_per_frame);
            }
            std::printf("}");
        }
        std::printf("]}\n");
        return;
    }
    std::printf("%-28s %11s %7s %5s %10s %10s %10s %10s %9s %7s %7s\n", "case", "size", "threads",
                "runs", "median ms", "min ms", "max ms", "cpu ms", "peak MB", "fps", "steady");
    std::printf(
        "(peak MB: resident memory while running the case: asset, frame, compositor\n"
        " buffers and the loaded libraries, not the bake before it; the bare process\n"
        " holds %.1f MB, mostly shared libraries)\n",
        baseline_mb);
    for (const Case& c : cases) {
        std::printf("%-28s %5dx%-5d %7d %5d %10.2f %10.2f %10.2f %10.2f %9.1f", c.name.c_str(),
                    c.width, c.height, c.threads, c.runs, c.median_ms, c.min_ms, c.max_ms,
                    c.median_cpu_ms, c.peak_rss_mb);
        if (c.fps > 0) std::printf(" %7.1f %7.1f", c.fps, c.steady_fps);
        std::printf("\n");
    }
}

}  // namespace

void setup_bench(CLI::App& sub) {
    auto a = std::make_shared<BenchArgs>();
    a->config = default_demo_config();
    sub.add_option("--repeats", a->repeats, "timed runs per case (median reported)");
    add_threads(sub, a->threads);
    sub.add_option("--config", a->config, "setup YAML (camera, rig, water)");
    sub.add_flag("--no-forward", a->no_forward, "time without forward scatter");
    sub.add_option("--scattering", a->scattering,
                   "single | multiple: the asset's scattering (multiple adds the lamps' "
                   "scattered light per pixel)");
    sub.add_option(
        "--cases", a->cases,
        "comma-separated prefixes of the cases to run: composite (composite, "
        "composite_final_only, each also -shadows: with lamp shadows; composite_small_angle: a "
        "multiple-scattering asset's all layers with and without its forward-scatter table, "
        "frame by frame in turn, as composite_transport_psf and composite_small_angle; "
        "composite_flat_port: all layers through a flat port, the asset baked through it, "
        "frame by frame in turn with composite_flat_port_base: the same without a port; "
        "composite_flat_port_pinhole: the pinhole asset through it), snow "
        "(snow-abyssal, "
        "snow-nepheloid, snow-plume: marine snow alone; snow-streaks: nepheloid as "
        "motion streaks, 1 m/s, 10 ms; snow-shadows: the nepheloid preset and lamp "
        "shadows together; snow-shadows-survey: the same on a close survey's frame, where the "
        "lamps cast shadows), shadows (lamp shadows alone; shadows-exact: the full-resolution "
        "sweep; shadows-survey: on the close survey's frame), stage, camera "
        "(camera, camera-layers, camera-codes, camera-lens), sequence-png, sequence-jpeg (each "
        "also -camera: with the setup's camera stage; -camera-snow-shadows: as the demo renders, "
        "with lamp shadows and abyssal marine snow besides)");
    sub.add_flag("--json", a->json, "print JSON for scripts");
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
