#include "cli_util.h"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "deepsea/bake/lattice_rule.h"
#include "deepsea/batch/snow_setup.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"

namespace deepsea::cli {

std::string default_demo_config() {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    // The program where the build put it reads the source tree's config; any other copy (an
    // installed one, a moved prefix) the one installed beside it.
    if (ec || fs::equivalent(exe, DEEPSEA_BUILT_PROGRAM, ec))
        return DEEPSEA_SOURCE_DIR "/volumes/demo.yaml";
    return (exe.parent_path() / DEEPSEA_DEMO_CONFIG_FROM_BINDIR).lexically_normal().string();
}

namespace {
/// Lock-free (parallel.h), so the handler may set it and long work polls it directly.
StopFlag g_signal{0};
}  // namespace

extern "C" void deepsea_on_stop_signal(int sig) { g_signal.store(sig); }

StopOnSignals::StopOnSignals() {
    struct sigaction sa {};
    sa.sa_handler = deepsea_on_stop_signal;
    sa.sa_flags = SA_RESETHAND;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &m_int);
    sigaction(SIGTERM, &sa, &m_term);
}

StopOnSignals::~StopOnSignals() {
    sigaction(SIGINT, &m_int, nullptr);
    sigaction(SIGTERM, &m_term, nullptr);
}

int stop_signal() { return g_signal.load(); }

extern "C" void deepsea_exit_on_signal(int sig) {
    // Only async-signal-safe calls: write(2) and _exit(2).
    const char* line = sig == SIGINT ? "deepsea: error: stopped by signal 2\n"
                                     : "deepsea: error: stopped by signal 15\n";
    std::size_t n = 0;
    while (line[n]) ++n;
    if (::write(STDERR_FILENO, line, n) < 0) {
        // nothing more can be said
    }
    ::_exit(130);  // Cancelled's code; no allocation here
}

void exit_on_signals() {
    struct sigaction sa {};
    sa.sa_handler = deepsea_exit_on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

namespace {
bool g_quiet = false, g_verbose = false;
}  // namespace

Verbosity verbosity() {
    return g_quiet ? Verbosity::Quiet : g_verbose ? Verbosity::Verbose : Verbosity::Normal;
}

void add_verbosity(CLI::App& sub) {
    CLI::Option* q =
        sub.add_flag("-q,--quiet", g_quiet, "no progress bar, no summary (errors still on stderr)");
    sub.add_flag("-v,--verbose", g_verbose, "a line per frame or item besides the summary")
        ->excludes(q);
}

void say(const char* format, ...) {
    if (verbosity() == Verbosity::Quiet) return;
    va_list args;
    va_start(args, format);
    std::vfprintf(stdout, format, args);
    va_end(args);
}

std::function<void(const FrameJob&, bool)> frame_lines() {
    if (verbosity() != Verbosity::Verbose) return {};
    return [](const FrameJob& job, bool skipped) {
        if (skipped) {
            detail("skipped %s (its outputs are complete)\n", job.rgb.c_str());
        } else {
            const std::string& out = job.output.empty() ? job.layers : job.output;
            detail("rendered %s -> %s%s%s\n", job.rgb.c_str(), out.c_str(),
                   job.output.empty() || job.layers.empty() ? "" : ", ",
                   job.output.empty() || job.layers.empty() ? "" : job.layers.c_str());
        }
    };
}

void detail(const char* format, ...) {
    if (verbosity() != Verbosity::Verbose) return;
    va_list args;
    va_start(args, format);
    std::vfprintf(stdout, format, args);
    va_end(args);
    std::fflush(stdout);
}

const StopFlag& stop_flag() { return g_signal; }

CLI::Option* add_threads(CLI::App& sub, int& threads) {
    const CLI::Validator non_negative(
        [](std::string& text) -> std::string {
            char* end = nullptr;
            const long v = std::strtol(text.c_str(), &end, 10);
            if (text.empty() || *end != '\0' || v < 0 || v > kMaxThreads)
                return "must be an integer from 0 (all cores) to " + std::to_string(kMaxThreads) +
                       " (more than the cores run as the cores), got '" + text + "'";
            return "";
        },
        "");
    return sub.add_option("--threads", threads, "worker threads (0: all cores)")
        ->check(non_negative);
}

void SetupFlags::add_to(CLI::App& sub, bool camera_required) {
    sub.add_option("--config", configs, "YAML file(s) with camera, rig and/or water sections")
        ->default_str("");
    sub.add_option("--camera", camera, "YAML file with a camera section");
    sub.add_option("--rig", rig, "YAML file with a rig section");
    sub.add_option("--water", water,
                   "YAML file with a water section, or a preset: jerlov:<TYPE>, deep:<TYPE>");
    (void)camera_required;
}

Setup SetupFlags::load() const {
    std::vector<std::string> files = configs;
    if (!camera.empty()) files.push_back(camera);
    if (!rig.empty()) files.push_back(rig);
    Setup setup = load_setup(files);
    if (!water.empty()) {
        if (setup.water)
            throw ConfigError("--water given but a config already has a water section");
        setup.water = load_water(water);
    }
    return setup;
}

std::vector<std::pair<std::string, std::string>> SetupFlags::inputs() const {
    std::vector<std::pair<std::string, std::string>> out;
    for (const std::string& c : configs) out.emplace_back(c, "the input --config");
    out.emplace_back(camera, "the input --camera");
    out.emplace_back(rig, "the input --rig");
    if (water.find(':') == std::string::npos) out.emplace_back(water, "the input --water");
    return out;
}

void DepthFlags::add_to(CLI::App& sub) {
    sub.add_option("--depth-channel", channel,
                   "channel of the depth file to use (Z, Y, R, depth, ...)");
    sub.add_option("--depth-scale", scale, "metres per unit for 16-bit depth images")
        ->check(CLI::PositiveNumber);
    sub.add_option("--depth-kind", kind,
                   "depth values are planar z (default) or range along the ray")
        ->check(CLI::IsMember({"z", "range"}));
}

DepthKind DepthFlags::depth_kind() const {
    return kind == "range" ? DepthKind::Range : DepthKind::Z;
}

void BakeFlags::add_to(CLI::App& sub) {
    sub.add_option("--xy-step", settings.step,
                   "pixels between lattice columns (default 0: auto, from the lamps' angular "
                   "detail, refined by the check)");
    sub.add_option("--depth-samples", settings.depth_samples,
                   "K: depth slabs per column (default 0: auto, 64, refined by the check)");
    sub.add_flag("--no-check", no_check,
                 "skip the bake's own accuracy check on a sample of pixels (and its refinement)");
    sub.add_flag("--strict-check", settings.strict,
                 "fail (exit 7, nothing written) if the bake's check misses the accuracy bar");
    sub.add_option("--depth-scheme", scheme, "uniform | taylor | sqrt | log");
    sub.add_option("--z-max", z_max,
                   "planar depth of the last sample in metres, 0.01 .. 1000, or 'auto'");
    sub.add_option("--tolerance", settings.tolerance,
                   "auto z-max: remaining backscatter / total beyond it");
    add_threads(sub, threads);
    sub.add_option("--scattering", scattering,
                   "single (the paper's model, exact) | multiple (all orders, Monte Carlo)");
    sub.add_option("--paths", settings.higher_orders.paths,
                   "multiple scattering: Monte Carlo paths per computed column, 1 .. " +
                       std::to_string(kMaxPaths) + " (64 x the default)");
    sub.add_option("--ms-stride", settings.higher_orders.stride,
                   "multiple scattering: computed on every n-th lattice column and row "
                   "(default 0: auto, spaced in angle by the light's angular detail)");
    sub.add_option("--seed", settings.higher_orders.seed, "multiple scattering: random seed");
}

Parallel BakeFlags::parallel(deepsea::Progress progress) const {
    return Parallel{threads, 0, std::move(progress)}.with_stop(&stop_flag());
}

BakeSettings BakeFlags::resolve() const {
    BakeSettings s = settings;
    s.scheme = parse_depth_scheme(scheme);
    s.scattering = parse_scattering(scattering);
    s.check = !no_check;
    if (z_max == "auto" || z_max.empty()) {
        s.z_max = 0.0;
    } else {
        char* end = nullptr;
        const double v = std::strtod(z_max.c_str(), &end);
        if (*end != '\0' || !(v > 0.0)) {
            throw ConfigError("--z-max: expected a depth > 0 in metres or 'auto', got '" + z_max +
                              "'");
        }
        static_assert(kMinZMax == 0.01 && kMaxZMax == 1000.0, "the message below");
        if (!(v >= kMinZMax && v <= kMaxZMax)) {
            throw ConfigError("--z-max: must be in [0.01, 1000] metres or 'auto', got '" + z_max +
                              "'");
        }
        s.z_max = v;
    }
    validate(s);
    return s;
}

std::string describe_check(const BakeInfo& info) {
    const LatticeCheck& c = info.check;
    if (!c.done) return "not checked (baked with --no-check)";
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "mean %.3f %%, max %.3f %% at pixel (%d, %d) (depth interpolation alone: mean "
                  "%.3f %%, max %.3f %%) on %ld test pixels%s; %s the bar (%.2f %% / %.0f %%)",
                  100.0 * c.mean_rel, 100.0 * c.max_rel, c.max_u, c.max_v,
                  100.0 * c.columns_mean_rel, 100.0 * c.columns_max_rel, c.pixels,
                  info.port ? " (exact integrals along the port's refracted rays)" : "",
                  meets_bar(c) ? "meets" : "MISSES", 100.0 * kBarMeanRel, 100.0 * kBarMaxRel);
    std::string out = buf;
    if (c.refinements > 0) {
        out += "; lattice refined " + std::to_string(c.refinements) + " time(s)";
    }
    return out;
}

std::optional<std::pair<int, int>> ShardFlags::resolve(bool environment_by_default) const {
    const bool given = option && option->count() > 0;
    const std::string& flag = text;
    const int k8s_count = count;
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
    const bool array = given && flag == "array";
    if (given && !array) {
        const auto slash = flag.find('/');
        if (slash == std::string::npos)
            throw ConfigError("--shard: expected i/n, got '" + flag + "'");
        i = parse_int(flag.substr(0, slash).c_str(), "--shard");
        n = parse_int(flag.substr(slash + 1).c_str(), "--shard");
    } else if (!array && !environment_by_default) {
        return std::nullopt;
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
    } else if (array) {
        throw ConfigError(
            "--shard array: neither SLURM_ARRAY_TASK_ID nor JOB_COMPLETION_INDEX is set (not an "
            "array job?); give --shard i/n");
    }
    if (n < 1 || i < 0 || i >= n) {
        throw ConfigError("shard " + std::to_string(i) + "/" + std::to_string(n) +
                          ": need 0 <= i < n");
    }
    return std::pair{i, n};
}

void ShardFlags::add_to(CLI::App& sub, const std::string& what) {
    option = sub.add_option("--shard", text,
                            "i/n: " + what +
                                "; 'array': the array job's SLURM_ARRAY_TASK_ID or "
                                "JOB_COMPLETION_INDEX; not empty");
    sub.add_option("--shard-count", count, "shards when JOB_COMPLETION_INDEX is used");
}

static double now_s() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

Progress::Progress(std::string label, long total)
    : m_label(std::move(label)),
      m_total(total),
      m_tty(isatty(STDERR_FILENO) && verbosity() == Verbosity::Normal),
      m_start(now_s()) {}

void Progress::update(long done) {
    if (!m_tty || m_total <= 0) return;
    const int width = 30;
    const int filled = int(width * done / m_total);
    const double dt = now_s() - m_start;
    std::fprintf(stderr, "\r%s [%.*s%*s] %ld/%ld  %.1f/s", m_label.c_str(), filled,
                 "##############################", width - filled, "", done, m_total,
                 dt > 0 ? done / dt : 0.0);
    std::fflush(stderr);
}

void Progress::finish() {
    if (m_tty) std::fprintf(stderr, "\n");
}

std::optional<SnowSettings> snow_settings(const std::string& preset, std::uint64_t seed,
                                          const std::optional<CameraModel>& model,
                                          const std::optional<Snow>& setup_snow) {
    if (preset == "off" || (preset.empty() && !setup_snow)) return std::nullopt;
    return make_snow_settings(preset.empty() ? *setup_snow : snow_preset(preset, "--snow"), seed,
                              model);
}

}  // namespace deepsea::cli
