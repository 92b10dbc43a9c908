#pragma once
/// \file The one way the library runs parallel work: a thread count, a grain size and a
/// progress/cancel callback (as OpenVDB's tools take an interrupter). Results never depend on
/// the thread count: bodies write disjoint outputs.

#include <cstddef>
#include <functional>

#include "deepsea/core/error.h"

namespace deepsea {

/// Called with (items done, items total) from one thread at a time, counts non-decreasing.
/// Return false to cancel: the running work stops at the next grain and parallel_for throws
/// Cancelled.
using Progress = std::function<bool(long done, long total)>;

/// How to run a long parallel operation.
struct Parallel {
    int threads = 0;          ///< worker threads; 0: all cores
    std::size_t grain = 1;    ///< items per task (at least 1)
    Progress progress;        ///< optional
};

/// The user (or a Progress callback) stopped a long operation.
class Cancelled : public Error {
public:
    using Error::Error;
    int exit_code() const override { return 130; }
};

/// Runs body(begin, end) over disjoint sub-ranges of [0, n) on par.threads workers, reporting
/// progress in items. Exceptions thrown by body propagate (the first one wins).
void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body,
                  const Parallel& par = {});

/// Runs f inside an arena of `threads` workers (0: all cores), for code that calls TBB or
/// OpenVDB's own parallel tools.
void in_arena(int threads, const std::function<void()>& f);

}  // namespace deepsea
