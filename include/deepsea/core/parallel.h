#pragma once
/// \file The one way the library runs parallel work: a thread count, a grain size and a
/// progress/cancel callback (as OpenVDB's tools take an interrupter). Results never depend on
/// the thread count: bodies write disjoint outputs.

#include <atomic>
#include <cstddef>
#include <functional>
#include <utility>

#include "deepsea/core/error.h"

namespace deepsea {

/// The most worker threads a caller may ask for. More than the machine's cores are run as the
/// cores (TBB would only warn and time-slice them).
inline constexpr int kMaxThreads = 1024;

/// ConfigError "threads: ..." unless 0 <= threads <= kMaxThreads.
void check_threads(int threads);

/// Called with (items done, items total) from one thread at a time, counts non-decreasing.
/// Return false to cancel: the running work stops at the next grain and parallel_for throws
/// Cancelled.
using Progress = std::function<bool(long done, long total)>;

/// A request to stop long work: non-zero once set, from any thread or a signal handler (it is
/// lock-free). Long operations poll it inside their items as well as between them (an adaptive
/// integral per panel, a Monte Carlo estimate per path), so that a stop lands within a small
/// fraction of a second however expensive one item is; the progress callback alone is asked
/// only when a whole grain of items is done.
using StopFlag = std::atomic<int>;
static_assert(StopFlag::is_always_lock_free, "a signal handler sets it");

/// The user (or a Progress callback) stopped a long operation.
class Cancelled : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 130; }
};

/// Throws Cancelled when `stop` is set (null: never). Cheap: one relaxed atomic load.
inline void throw_if_stopped(const StopFlag* stop) {
    if (stop && stop->load(std::memory_order_relaxed) != 0) throw Cancelled("cancelled");
}

/// How to run a long parallel operation. Library functions take it last, defaulted, so that a
/// caller names only what it cares about: `bake(cam, rig, water, settings, {threads, 0, bar})`.
struct Parallel {
    int threads = 0;                 ///< worker threads, 0 to kMaxThreads; 0: all cores
    std::size_t grain = 0;           ///< items per task; 0: the operation's own choice
    Progress progress;               ///< optional
    const StopFlag* stop = nullptr;  ///< optional: polled inside and between items

    Parallel() = default;
    /// Not explicit: a call can pass `{threads}` or `{threads, grain, progress}`.
    Parallel(int threads_, std::size_t grain_ = 0, Progress progress_ = {})
        : threads(threads_), grain(grain_), progress(std::move(progress_)) {}

    /// A copy with grain `g` unless the caller chose one: how an operation states the task
    /// size that suits its items (a lattice column, an image row).
    Parallel or_grain(std::size_t g) const {
        Parallel p = *this;
        if (p.grain == 0) p.grain = g;
        return p;
    }

    /// A copy that also stops when `flag` is set.
    Parallel with_stop(const StopFlag* flag) const {
        Parallel p = *this;
        p.stop = flag;
        return p;
    }
};

/// Runs body(begin, end) over disjoint sub-ranges of [0, n), each at most par.grain items
/// (grain 0 counts as 1), on par.threads workers, reporting progress in items. Exceptions
/// thrown by body propagate (the first one wins); Cancelled when the progress callback returns
/// false or par.stop is set (checked before every grain and at the end); ConfigError for
/// threads < 0.
void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body,
                  const Parallel& par = {});

/// Runs f inside an arena of `threads` workers (0: all cores), for code that calls TBB or
/// OpenVDB's own parallel tools. ConfigError for threads < 0.
void in_arena(int threads, const std::function<void()>& f);

}  // namespace deepsea
