// deepsea bench: times the compositor alone (no file I/O) on generated frames, and a sequence
// render with I/O. Medians over repeated runs; peak memory from getrusage.

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
#include <utility>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/jerlov.h"
#include "deepsea/runtime/asset_backscatter.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/lamps.h"
#include "deepsea/runtime/sequence.h"
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
    std::string config = std::string(DEEPSEA_SOURCE_DIR) + "/volumes/demo.yaml";
};

struct Case {
    std::string name;
    int width = 0, height = 0, threads = 0, runs = 0;
    double median_ms = 0, min_ms = 0, max_ms = 0, peak_rss_mb = 0;
    double median_cpu_ms = 0;  ///< the process's CPU time (all threads) per run
};

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

/// Composites one generated frame repeatedly, for each layer set (all layers, then only the
/// image): one bake and one frame per camera, a fresh compositor and peak window per case.
std::vector<Case> time_compositor(const Setup& setup, const Camera& cam, const BenchArgs& a,
                                  int threads) {
    Water water = *setup.water;
    if (a.no_forward) water.forward.enabled = false;
    const Asset asset = bake(cam, *setup.rig, water, bench_bake(a));
    FlightParams flight;
    flight.camera = cam;
    const Frame frame = render_flight_frame(flight, 0);
    const AnalyticLamps lamps(*setup.rig, water, asset.lamp_fields);
    const AssetBackscatter backscatter(asset, cam);
    std::vector<Case> cases;
    for (LayerSet set : {LayerSet::All, LayerSet::Final}) {
        // From here on only what the runtime holds: the asset, one frame, the compositor.
        reset_peak_rss();
        Compositor comp(cam, water, lamps, backscatter);
        Layers layers;
        comp.composite(layers, frame, set);  // first frame allocates
        std::vector<double> t, cpu;
        for (int r = 0; r < a.repeats; ++r) {
            const double t0 = now_ms(), c0 = cpu_ms();
            comp.composite(layers, frame, set);
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
        }
        cases.push_back(summarize(set == LayerSet::All ? "composite" : "composite_final_only",
                                  cam.width, cam.height, threads, t, cpu));
    }
    return cases;
}

Case time_sequence(const Setup& setup, const BenchArgs& a, int threads) {
    const Camera& cam = *setup.camera;
    const Asset asset = bake(cam, *setup.rig, *setup.water, bench_bake(a));
    const fs::path dir = fs::temp_directory_path() / ("deepsea-bench-" + std::to_string(getpid()));
    fs::create_directories(dir / "out");
    FlightParams flight;
    flight.camera = cam;
    std::vector<FrameJob> jobs;
    const int n = 8;
    for (int i = 0; i < n; ++i) {
        const Frame f = render_flight_frame(flight, i);
        FrameJob j;
        j.rgb = (dir / ("f" + std::to_string(i) + ".png")).string();
        j.depth = (dir / ("f" + std::to_string(i) + "_depth.exr")).string();
        j.output = (dir / "out" / ("f" + std::to_string(i) + ".png")).string();
        write_color(j.rgb, f.rgb);
        write_depth_exr(j.depth, f.depth);
        jobs.push_back(j);
    }
    reset_peak_rss();
    std::vector<double> t, cpu;
    for (int r = 0; r < std::max(3, a.repeats / 7); ++r) {
        const double c0 = cpu_ms();
        const SequenceResult res = render_sequence(asset, jobs, SequenceOptions{});
        if (!res.errors.empty()) throw IoError("bench sequence failed: " + res.errors.front());
        t.push_back(res.seconds * 1000.0 / n);
        cpu.push_back((cpu_ms() - c0) / n);
    }
    fs::remove_all(dir);
    return summarize("sequence_with_io_per_frame", cam.width, cam.height, threads, t, cpu);
}

void run(const BenchArgs& a) {
    if (a.repeats < 1) throw ConfigError("--repeats must be >= 1");
    // Resident memory before any work: mostly the shared libraries that Debian's OpenImageIO
    // pulls in (about 270 of them), counted in every case's peak.
    const double baseline_mb = status_kb("VmRSS: %lf kB") / 1024.0;
    const int threads = a.threads > 0 ? a.threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Setup setup = load_setup({a.config});
    require_complete(setup, a.config);
    std::vector<Case> cases;
    for (const auto& [w, h] : {std::pair{800, 800}, std::pair{1920, 1080}}) {
        for (Case& c : time_compositor(setup, scaled(*setup.camera, w, h), a, threads)) {
            cases.push_back(std::move(c));
        }
    }
    cases.push_back(time_sequence(setup, a, threads));
    if (a.json) {
        std::printf("{\"baseline_rss_mb\": %.1f, \"scattering\": \"%s\", \"cases\": [", baseline_mb,
                    a.scattering.c_str());
        for (std::size_t i = 0; i < cases.size(); ++i) {
            const Case& c = cases[i];
            std::printf(
                "%s{\"name\": \"%s\", \"width\": %d, \"height\": %d, \"threads\": %d, "
                "\"runs\": %d, \"median_ms\": %.3f, \"min_ms\": %.3f, \"max_ms\": %.3f, "
                "\"median_cpu_ms\": %.3f, \"peak_rss_mb\": %.1f}",
                i ? ", " : "", c.name.c_str(), c.width, c.height, c.threads, c.runs, c.median_ms,
                c.min_ms, c.max_ms, c.median_cpu_ms, c.peak_rss_mb);
        }
        std::printf("]}\n");
        return;
    }
    std::printf("%-28s %11s %7s %5s %10s %10s %10s %10s %9s\n", "case", "size", "threads", "runs",
                "median ms", "min ms", "max ms", "cpu ms", "peak MB");
    std::printf(
        "(peak MB: resident memory while running the case: asset, frame, compositor\n"
        " buffers and the loaded libraries, not the bake before it; the bare process\n"
        " holds %.1f MB, mostly shared libraries)\n",
        baseline_mb);
    for (const Case& c : cases) {
        std::printf("%-28s %5dx%-5d %7d %5d %10.2f %10.2f %10.2f %10.2f %9.1f\n", c.name.c_str(),
                    c.width, c.height, c.threads, c.runs, c.median_ms, c.min_ms, c.max_ms,
                    c.median_cpu_ms, c.peak_rss_mb);
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
    sub.add_flag("--json", a->json, "print JSON for scripts");
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
