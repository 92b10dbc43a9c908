#pragma once
/// \file Small helpers shared by the subcommands: config loading from flags, progress bars.

#include <CLI/CLI.hpp>
#include <csignal>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/bake/bake.h"
#include "deepsea/batch/frame_jobs.h"
#include "deepsea/io/config.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/camera.h"
#include "deepsea/runtime/marine_snow.h"

namespace deepsea::cli {

/// The demo's setup file, the default --config of `demo` and `bench`: beside the installed
/// program, `<prefix>/share/deepsea/demo.yaml` (found from the program's folder, so a moved
/// prefix finds its own); for the program where the build put it, the source tree's
/// volumes/demo.yaml.
std::string default_demo_config();

/// Marine snow from `--snow PRESET|off` (unset for off; ConfigError naming --snow for an
/// unknown preset), or where `preset` is empty (no --snow) the setup's `snow` section; its seed
/// and the lens (the camera model's where given, else the default lens: f-number, pixel pitch,
/// focus distance).
std::optional<SnowSettings> snow_settings(const std::string& preset, std::uint64_t seed,
                                          const std::optional<CameraModel>& model,
                                          const std::optional<Snow>& setup_snow = {});

/// --threads: worker threads, 0 (the default) for all cores; "must be an integer >= 0"
/// otherwise. Every command that computes adds it through here.
CLI::Option* add_threads(CLI::App& sub, int& threads);

/// --config (repeatable), --camera, --rig, --water (file or preset).
struct SetupFlags {
    std::vector<std::string> configs;
    std::string camera, rig, water;
    void add_to(CLI::App& sub, bool camera_required = true);
    /// Loads all files; throws ConfigError if a section is missing.
    Setup load() const;
    /// The config files given (a water preset is no file), each with its flag, for
    /// require_distinct: no output may replace them.
    std::vector<std::pair<std::string, std::string>> inputs() const;
};

/// --depth-channel, --depth-scale, --depth-kind.
struct DepthFlags {
    std::string channel;
    double scale = 0.001;
    std::string kind = "z";
    void add_to(CLI::App& sub);
    DepthReadOptions read_options() const { return {channel, scale}; }
    DepthKind depth_kind() const;
};

/// --xy-step, --depth-samples, --depth-scheme, --z-max, --tolerance, --threads, --no-check,
/// --strict-check, and the multiple-scattering flags.
struct BakeFlags {
    BakeSettings settings;
    std::string scheme = to_string(BakeSettings{}.scheme);
    std::string z_max = "auto";  ///< or a depth in metres
    std::string scattering = "single";
    bool no_check = false;  ///< --no-check
    int threads = 0;        ///< how to run, not what to bake: not part of the settings
    void add_to(CLI::App& sub);
    /// Settings with the flags applied; ConfigError for a bad value.
    BakeSettings resolve() const;
    /// --threads, with `progress` (may be empty), stopping when stop_flag() is set (a signal
    /// while StopOnSignals is in scope).
    Parallel parallel(deepsea::Progress progress = {}) const;
};

/// --shard i/n (or `array`) and --shard-count: which part of a list of work items (a library's
/// assets, a sequence's frames) this process does, for a cluster's array jobs.
struct ShardFlags {
    std::string text;
    int count = 0;  ///< --shard-count, for JOB_COMPLETION_INDEX
    CLI::Option* option = nullptr;
    /// `what`: what shard i of n does, for --help.
    void add_to(CLI::App& sub, const std::string& what);
    /// (index, count): --shard i/n; with --shard array, or without --shard when
    /// `environment_by_default`, an array job's variables: SLURM_ARRAY_TASK_ID - _MIN of
    /// SLURM_ARRAY_TASK_COUNT, else JOB_COMPLETION_INDEX of --shard-count. Unset when no shard
    /// was asked for. ConfigError for '' (an unset shell variable: it used to bake the whole
    /// library on every array task), text that is not i/n with 0 <= i < n, or `array` outside
    /// an array job.
    std::optional<std::pair<int, int>> resolve(bool environment_by_default) const;
};

/// One line on an asset's own accuracy check (BakeInfo::check) for bake and info: the
/// errors, where the worst pixel is, how many pixels, refinements, and whether it meets the bar.
std::string describe_check(const BakeInfo& info);

/// While one is in scope, SIGINT and SIGTERM ask long work to stop: stop_signal() turns
/// non-zero and the commands' progress callbacks return false, so that only complete outputs
/// remain. A second signal of the same kind ends the process at once.
class StopOnSignals {
public:
    StopOnSignals();
    ~StopOnSignals();
    StopOnSignals(const StopOnSignals&) = delete;
    StopOnSignals& operator=(const StopOnSignals&) = delete;

private:
    struct sigaction m_int {
    }, m_term{};
};

/// From main, for the whole run: SIGINT or SIGTERM outside a StopOnSignals (startup, short
/// commands) ends the process at once with one line and exit code 130, as a stopped long
/// command does, instead of the shell's 128 + signal (143 for SIGTERM). Outputs are written
/// atomically, so nothing half-written is left.
void exit_on_signals();

/// How much a command says on stdout: -q (progress bars and summaries off; a command's own
/// output, such as info's report or bench's table, and warnings and errors on stderr stay),
/// -v (a line per frame or item besides; the progress bar gives way to them).
enum class Verbosity { Quiet, Normal, Verbose };
Verbosity verbosity();
/// -q/--quiet and -v/--verbose on a subcommand (main adds them to every one).
void add_verbosity(CLI::App& sub);
/// printf to stdout unless -q: summaries, "wrote ...".
void say(const char* format, ...) __attribute__((format(printf, 1, 2)));
/// printf to stdout with -v only: one line per frame or item.
void detail(const char* format, ...) __attribute__((format(printf, 1, 2)));

/// With -v: a line per frame of a sequence render (SequenceOptions::on_frame); else empty.
std::function<void(const FrameJob&, bool)> frame_lines();

/// The signal that asked to stop, 0 if none.
int stop_signal();

/// The same as a flag for long work to poll (Parallel::stop): set by the first SIGINT or
/// SIGTERM while a StopOnSignals is in scope, so that a stop reaches inside one long item
/// (a lattice column, a Monte Carlo column) instead of waiting for it to end.
const StopFlag& stop_flag();

/// A one-line progress bar on stderr when it is a terminal; silent otherwise, with -q or -v.
class Progress {
public:
    Progress(std::string label, long total);
    void update(long done);
    void set_total(long total) { m_total = total; }
    void finish();

private:
    std::string m_label;
    long m_total;
    bool m_tty;
    double m_start;
};

}  // namespace deepsea::cli
