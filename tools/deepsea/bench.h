#pragma once
// deepsea bench's shared pieces (cmd_bench.cpp runs the cases): its options, one case's
// result, the clocks (wall, the process's CPU time, peak memory) and the renderer's cases
// (bench_render.cpp: the compositor, marine snow, lamp shadows).

#include <string>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/bake/bake.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"

namespace deepsea::cli::bench {

struct BenchArgs {
    int repeats = 21;
    int threads = 0;
    bool json = false;
    bool no_forward = false;
    std::string scattering = "single";
    std::string cases = "composite,stage,camera,sequence";
    std::string config;  ///< the setup (default_demo_config() when set up by the CLI)
};

struct Case {
    std::string name;
    int width = 0, height = 0, threads = 0, runs = 0;
    double median_ms = 0, min_ms = 0, max_ms = 0, peak_rss_mb = 0;
    double median_cpu_ms = 0;              ///< the process's CPU time (all threads) per run
    double fps = 0, cpu_ms_per_frame = 0;  ///< sequence cases only (0: not printed)
    /// Sequence cases: the rate once the pipeline is full (from the kSteadyFrom-th frame
    /// written to the last), without the sequence's start: a long sequence's rate.
    double steady_fps = 0, steady_cpu_ms_per_frame = 0;
};

/// True if `name` starts with one of the comma-separated prefixes in `list`.
bool wanted(const std::string& list, const std::string& name);
/// A /proc/self/status field in kB (0 if unavailable), e.g. "VmRSS: %lf kB".
double status_kb(const char* format);
/// Peak resident memory (VmHWM) since the last reset_peak_rss(), in MB.
double peak_rss_mb();
/// Starts a new peak-memory window (Linux: clear_refs 5), after returning freed memory to the
/// system, so that a case's peak is its own and not the bake's or the scene generator's.
void reset_peak_rss();
/// Wall clock, ms.
double now_ms();
/// CPU time of the whole process (every thread), ms: unlike wall time, barely changed by other
/// processes competing for the cores.
double cpu_ms();
/// Median, minimum and maximum of the runs' wall times, median of their CPU times, peak memory.
Case summarize(std::string name, int w, int h, int threads, std::vector<double> t,
               std::vector<double> cpu);
/// The asset the cases composite with. Multiple scattering is baked with few Monte Carlo
/// samples: the runtime's work per pixel does not depend on them, only the bake's time.
BakeSettings bench_bake(const BenchArgs& a);
/// True if every prefix in `list` names a shadows case (no asset needed: no bake).
bool only_shadows(const std::string& list);
/// The demo camera's view at another resolution (same horizontal field of view).
Camera scaled(const Camera& base, int w, int h);

/// True if `list` asks for any of the compositor's cases.
bool wants_compositor(const std::string& list);
/// The compositor's cases (bench_render.cpp).
std::vector<Case> time_compositor(const Asset& asset, const Camera& cam, const BenchArgs& a,
                                  int threads);
/// Marine snow alone at each preset's density.
std::vector<Case> time_snow(const Asset& asset, const Camera& cam, const BenchArgs& a, int threads);
/// Lamp shadows alone.
std::vector<Case> time_shadows(const Camera& cam, const Rig& rig, const BenchArgs& a, int threads);

}  // namespace deepsea::cli::bench
