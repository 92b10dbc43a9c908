// deepsea bench's clocks and shared helpers (bench.h).

#include <malloc.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>

#include "bench.h"
#include "cli_util.h"

namespace deepsea::cli::bench {

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

bool wants_compositor(const std::string& list) {
    for (const char* n :
         {"composite", "composite_final_only", "composite-shadows", "composite_final_only-shadows",
          "composite_flat_port", "composite_flat_port_pinhole", "composite_small_angle"}) {
        if (wanted(list, n)) return true;
    }
    return false;
}

}  // namespace deepsea::cli::bench
