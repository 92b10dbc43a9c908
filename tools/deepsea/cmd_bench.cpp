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

struct BenchArgs {
    int repeats = 21;
    int threads = 0;
    bool json = false;
    bool no_forward = false;
    std::string scattering = "single";
    std::string cases = "composite,stage,camera,sequence";
    std::string config = default_demo_config();
};

struct Case {
    std::string name;
    int width = 0, height = 0, threads = 0, runs = 0;
    double median_ms = 0, min_ms = 0, max_ms = 0, peak_rss_mb = 0;
    double median_cpu_ms = 0;              ///< the process's CPU time (all threads) per run
    double fps = 0, cpu_ms_per_frame = 0;  ///< sequence cases only (0: not printed)
};

/// True if `name` starts with one of the comma-separated prefixes in `list`.
bool wanted(const std::string& list, const std::string& name) {
    std::size_t b = 0;
    while (b <= list.size()) {
        const std::size_t e = std::min(list.find(',', b), list.size());
        const std::string p = list.substr(b, e - b);
        if (!p.empty() && name.compare(0, p.size(), p) == 0) return true;
        b = e + 1;
    }
    return false;
}

/// A /proc/self/status field in kB (0 if unavailable).
double status_kb(const char* format) {
    std::FILE* f = std::fopen("/proc/self/status", "r");
    double kb = 0.0;
    if (f) {
        char line[256];
        while (std::fgets(line, sizeof line, f)) {
            if (std::sscanf(line, format, &kb) == 1) break;
        }
        std::fclose(f);
    }
    return kb;
}

/// Peak resident memory (VmHWM) since the last reset_peak_rss(), in MB.
double peak_rss_mb() {
    double kb = status_kb("VmHWM: %lf kB");
    if (kb == 0.0) {
        rusage ru{};
        getrusage(RUSAGE_SELF, &ru);
        kb = double(ru.ru_maxrss);
    }
    return kb / 1024.0;
}

/// Starts a new peak-memory window (Linux: clear_refs 5), after returning freed memory to the
/// system, so that a case's peak is its own and not the bake's or the scene generator's.
void reset_peak_rss() {
    malloc_trim(0);
    if (std::FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
        std::fputs("5", f);
        std::fclose(f);
    }
}

double now_ms() {
    using namespace std::chrono;
    return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

/// CPU time of the whole process (every thread), ms: unlike wall time, barely changed by other
/// processes competing for the cores.
double cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

Case summarize(std::string name, int w, int h, int threads, std::vector<double> t,
               std::vector<double> cpu) {
    std::sort(t.begin(), t.end());
    std::sort(cpu.begin(), cpu.end());
    Case c{std::move(name), w, h, threads, int(t.size())};
    c.median_ms = t[t.size() / 2];
    c.min_ms = t.front();
    c.max_ms = t.back();
    c.peak_rss_mb = peak_rss_mb();
    c.median_cpu_ms = cpu[cpu.size() / 2];
    return c;
}

/// The asset the cases composite with. Multiple scattering is baked with few Monte Carlo
/// samples: the runtime's work per pixel does not depend on them, only the bake's time.
BakeSettings bench_bake(const BenchArgs& a) {
    BakeSettings s;
    s.scattering = parse_scattering(a.scattering);
    s.higher_orders.paths = 256;
    s.higher_orders.lamp_samples = 64;
    return s;
}

/// True if every prefix in `list` names a shadows case (no asset needed: no bake).
bool only_shadows(const std::string& list) {
    std::size_t b = 0;
    while (b <= list.size()) {
        const std::size_t e = std::min(list.find(',', b), list.size());
        const std::string p = list.substr(b, e - b);
        if (p.size() < 7 || p.compare(0, 7, "shadows") != 0) return false;
        b = e + 1;
    }
    return true;
}

/// The demo camera's view at another resolution (same horizontal field of view).
Camera scaled(const Camera& base, int w, int h) {
    Camera c = base;
    c.width = w;
    c.height = h;
    c.fx = c.fy = base.fx * double(w) / base.width;
    c.cx = (w - 1) / 2.0;
    c.cy = (h - 1) / 2.0;
    return c;
}

/// The compositor's cases: each layer set (all layers, then only the image), without and with
/// lamp shadows.
const char* const kCompositeCases[] = {"composite", "composite_final_only", "composite-shadows",
                                       "composite_final_only-shadows"};

/// Composites one generated frame repeatedly, for each layer set (all layers, then only the
/// image), without and with lamp shadows, then all layers through a flat port (an asset baked
/// through it, and the pinhole asset): one frame per camera, a fresh compositor and peak window
/// per case.
std::vector<Case> time_compositor(const Asset& asset, const Camera& cam, const BenchArgs& a,
                                  int threads) {
    FlightParams flight;
    flight.camera = cam;
    Frame frame = render_flight_frame(flight, 0);
    std::vector<Case> cases;
    const auto time = [&](const std::string& name, const RenderSettings& settings, LayerSet set,
                          const Asset* other = nullptr) {
        Renderer renderer(other ? *other : asset, settings);
        // From here on only what the runtime holds: the asset, one frame, the compositor (made
        // by the first frame, which also allocates).
        reset_peak_rss();
        Layers layers;
        renderer.render(layers, frame, set);
        std::vector<double> t, cpu;
        for (int r = 0; r < a.repeats; ++r) {
            const double t0 = now_ms(), c0 = cpu_ms();
            renderer.render(layers, frame, set);
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
        }
        cases.push_back(summarize(name, cam.width, cam.height, threads, t, cpu));
    };
    for (int k = 0; k < 4; ++k) {
        if (!wanted(a.cases, kCompositeCases[k])) continue;
        RenderSettings settings{cam};
        settings.shadows = k >= 2;
        time(kCompositeCases[k], settings, k % 2 == 0 ? LayerSet::All : LayerSet::Final);
    }
    if (asset.forward_psf && wanted(a.cases, "composite_small_angle")) {
        // All layers with the asset's forward scatter from transport and, frame by frame in
        // turn, with the small-angle point spread that assets without the table get: paired
        // timings, so that the machine's drift does not fall on one of the two.
        Asset small_angle = asset;
        small_angle.forward_psf.reset();
        Renderer table(asset, RenderSettings{cam}), small(small_angle, RenderSettings{cam});
        Layers lt, ls;
        table.render(lt, frame, LayerSet::All);
        small.render(ls, frame, LayerSet::All);
        std::vector<double> t[2], cpu[2];
        for (int r = 0; r < a.repeats; ++r) {
            for (int k = 0; k < 2; ++k) {
                const double t0 = now_ms(), c0 = cpu_ms();
                (k == 0 ? table : small).render(k == 0 ? lt : ls, frame, LayerSet::All);
                t[k].push_back(now_ms() - t0);
                cpu[k].push_back(cpu_ms() - c0);
            }
        }
        cases.push_back(
            summarize("composite_transport_psf", cam.width, cam.height, threads, t[0], cpu[0]));
        cases.push_back(
            summarize("composite_small_angle", cam.width, cam.height, threads, t[1], cpu[1]));
    }
    RenderSettings port_settings{cam};
    port_settings.port = Port{};
    port_settings.port->flat.distance = 0.03;
    port_settings.port->flat.glass_thickness = 0.012;
    if (wanted(a.cases, "composite_flat_port")) {
        // Through a flat port (3 cm from the camera centre, 1.2 cm of acrylic, seawater): every
        // pixel's water-side ray marched through the frame's depth (docs/ports.md), the asset
        // baked through the port (its columns the water-side rays, looked up as a pinhole
        // frame's).
        BakeSettings through = bench_bake(a);
        through.port = port_settings.port;
        const Asset port_asset = bake(cam, asset.info.rig, asset.info.water, through);
        time("composite_flat_port", port_settings, LayerSet::All, &port_asset);
    }
    // The same with the pinhole asset, looked up through the port (port_backscatter.h).
    if (wanted(a.cases, "composite_flat_port_pinhole"))
        time("composite_flat_port_pinhole", port_settings, LayerSet::All);
    return cases;
}

/// Marine snow alone (MarineSnow::draw: placing, lighting and drawing the particles into the
/// image) at each preset's density, on the flight's first frame, the camera moving along the
/// flight from one run to the next (particles fixed in the world).
std::vector<Case> time_snow(const Asset& asset, const Camera& cam, const BenchArgs& a,
                            int threads) {
    std::vector<Case> cases;
    FlightParams flight;
    flight.camera = cam;
    const Frame frame = render_flight_frame(flight, 0);
    for (const std::string& preset : snow_preset_names()) {
        const std::string name = "snow-" + preset;
        if (!wanted(a.cases, name)) continue;
        SnowSettings s;
        s.snow = snow_preset(preset);
        MarineSnow snow(s, asset.info.rig, asset.info.water);
        Image final(cam.width, cam.height, 3);
        std::vector<double> t, cpu;
        long particles = 0;
        for (int r = 0; r <= a.repeats; ++r) {
            const FlightPose p = flight_pose(flight, r);
            snow.set_frame(std::uint64_t(r), CameraPose{p.origin, p.right, p.down, p.forward});
            const double t0 = now_ms(), c0 = cpu_ms();
            snow.draw(cam, frame.depth, final, nullptr, nullptr);
            if (r == 0) continue;  // the first run allocates
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
            particles += snow.drawn();
        }
        detail("%s: %ld particles drawn per frame on average\n", name.c_str(),
               particles / std::max(a.repeats, 1));
        cases.push_back(summarize(name, cam.width, cam.height, threads, t, cpu));
    }
    return cases;
}

/// Lamp shadows alone (LampShadows::compute: every lamp's visibility image) on the flight's
/// first frame with the setup's rig: `shadows` as rendered, `shadows-exact` the full-resolution
/// sweep it is checked against (docs/runtime.md, "Lamp shadows").
std::vector<Case> time_shadows(const Camera& cam, const Rig& rig, const BenchArgs& a, int threads) {
    std::vector<Case> cases;
    FlightParams flight;
    flight.camera = cam;
    const Frame frame = render_flight_frame(flight, 0);
    for (const bool exact : {false, true}) {
        const std::string name = exact ? "shadows-exact" : "shadows";
        if (!wanted(a.cases, name)) continue;
        ShadowSettings s{true};
        if (exact) s.step = 1;
        LampShadows shadows;
        shadows.compute(cam, frame.depth, rig, s);  // the first run allocates
        std::vector<double> t, cpu;
        for (int r = 0; r < a.repeats; ++r) {
            const double t0 = now_ms(), c0 = cpu_ms();
            shadows.compute(cam, frame.depth, rig, s);
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
        }
        cases.push_back(summarize(name, cam.width, cam.height, threads, t, cpu));
    }
    return cases;
}

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
    Renderer renderer(asset, {cam});
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
    Renderer renderer(asset, {cam});
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
/// `render --camera` does.
std::vector<Case> time_sequences(const Asset& asset, const Camera& cam, const BenchArgs& a,
                                 int threads, const std::optional<CameraModel>& model) {
    if (!wanted(a.cases, "sequence-png") && !wanted(a.cases, "sequence-jpeg")) return {};
    const TempFolder tmp("sequence");
    fs::create_directories(tmp.dir / "out");
    FlightParams flight;
    flight.camera = cam;
    constexpr int kFrames = 16, kGenerated = 2;
    for (int i = 0; i < kGenerated; ++i) {
        const Frame f = render_flight_frame(flight, i);
        write_color((tmp.dir / ("f" + std::to_string(i) + ".png")).string(), f.rgb);
        write_depth_exr((tmp.dir / ("f" + std::to_string(i) + "_depth.exr")).string(), f.depth);
    }
    std::vector<Case> cases;
    for (const char* ext : {".png", ".jpg"}) {
        for (const bool camera : {false, true}) {
            const std::string name =
                std::string(ext == std::string(".png") ? "sequence-png" : "sequence-jpeg") +
                (camera ? "-camera" : "");
            if (!wanted(a.cases, name)) continue;
            std::vector<FrameJob> jobs;
            for (int i = 0; i < kFrames; ++i) {
                const std::string g = std::to_string(i % kGenerated), k = std::to_string(i);
                const fs::path rgb = tmp.dir / ("in" + k + ".png"),
                               depth = tmp.dir / ("in" + k + ".exr");
                if (!fs::exists(rgb)) fs::copy_file(tmp.dir / ("f" + g + ".png"), rgb);
                if (!fs::exists(depth)) fs::copy_file(tmp.dir / ("f" + g + "_depth.exr"), depth);
                jobs.push_back({rgb.string(), depth.string(),
                                (tmp.dir / "out" / (k + ext)).string(), "", std::nullopt});
            }
            SequenceOptions opt;
            opt.forward = !a.no_forward;
            if (camera) {
                opt.camera_model = model ? *model : CameraModel{};
                opt.layer_output.camera = true;
            }
            reset_peak_rss();
            std::vector<double> wall, cpu;
            for (int r = 0; r < 3; ++r) {
                const double c0 = cpu_ms();
                const SequenceResult res = render_sequence(asset, jobs, opt);
                cpu.push_back((cpu_ms() - c0) / kFrames);
                if (!res.errors.empty())
                    throw IoError("bench sequence failed: " + res.errors.front());
                wall.push_back(res.seconds * 1000.0 / kFrames);
            }
            Case c = summarize(name, cam.width, cam.height, threads, wall, cpu);
            c.cpu_ms_per_frame = c.median_cpu_ms;
            c.fps = 1000.0 / c.median_ms;
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
        if (wanted(a.cases, "composite_flat_port") ||
            wanted(a.cases, "composite_flat_port_pinhole") ||
            wanted(a.cases, "composite_small_angle") ||
            std::any_of(std::begin(kCompositeCases), std::end(kCompositeCases),
                        [&](const char* n) { return wanted(a.cases, n); })) {
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
                std::printf(", \"fps\": %.2f, \"cpu_ms_per_frame\": %.2f", c.fps,
                            c.cpu_ms_per_frame);
            }
            std::printf("}");
        }
        std::printf("]}\n");
        return;
    }
    std::printf("%-28s %11s %7s %5s %10s %10s %10s %10s %9s %7s\n", "case", "size", "threads",
                "runs", "median ms", "min ms", "max ms", "cpu ms", "peak MB", "fps");
    std::printf(
        "(peak MB: resident memory while running the case: asset, frame, compositor\n"
        " buffers and the loaded libraries, not the bake before it; the bare process\n"
        " holds %.1f MB, mostly shared libraries)\n",
        baseline_mb);
    for (const Case& c : cases) {
        std::printf("%-28s %5dx%-5d %7d %5d %10.2f %10.2f %10.2f %10.2f %9.1f", c.name.c_str(),
                    c.width, c.height, c.threads, c.runs, c.median_ms, c.min_ms, c.max_ms,
                    c.median_cpu_ms, c.peak_rss_mb);
        if (c.fps > 0) std::printf(" %7.1f", c.fps);
        std::printf("\n");
    }
}

}  // namespace

void setup_bench(CLI::App& sub) {
    auto a = std::make_shared<BenchArgs>();
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
        "composite_flat_port: all layers through a flat port, the asset baked through it, and "
        "composite_flat_port_pinhole: the pinhole asset through it), snow "
        "(snow-abyssal, "
        "snow-nepheloid, snow-plume: marine snow alone), shadows (lamp shadows alone; "
        "shadows-exact: the full-resolution sweep), stage, camera "
        "(camera, camera-layers, camera-codes, camera-lens), sequence-png, sequence-jpeg (each "
        "also -camera: with the setup's camera stage)");
    sub.add_flag("--json", a->json, "print JSON for scripts");
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
