#include "deepsea/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <string>

namespace deepsea {

void check_threads(int threads) {
    if (threads < 0 || threads > kMaxThreads) {
        throw ConfigError("threads: must be an integer from 0 (all cores) to " +
                          std::to_string(kMaxThreads) + ", got " + std::to_string(threads));
    }
}

void in_arena(int threads, const std::function<void()>& f) {
    check_threads(threads);
    if (threads > 0) {
        tbb::task_arena arena(std::min(threads, tbb::info::default_concurrency()));
        arena.execute(f);
    } else {
        f();
    }
}

namespace {

/// Progress from worker threads: a counter, and the callback under a mutex so that the caller
/// sees one call at a time with a non-decreasing count.
class ProgressCounter {
public:
    ProgressCounter(const Progress& cb, long total) : m_cb(cb), m_total(total) {}

    /// Adds n items; false once the callback asked to stop.
    bool add(long n) {
        const long done = m_done.fetch_add(n) + n;
        if (!m_cb) return !m_stop.load();
        std::lock_guard<std::mutex> lock(m_mutex);
        if (done > m_reported && !m_stop) {
            m_reported = done;
            if (!m_cb(done, m_total)) m_stop = true;
        }
        return !m_stop;
    }
    bool stopped() const { return m_stop.load(); }

private:
    const Progress& m_cb;
    long m_total;
    std::atomic<long> m_done{0};
    long m_reported = 0;
    std::atomic<bool> m_stop{false};
    std::mutex m_mutex;
};

}  // namespace

void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body,
                  const Parallel& par) {
    check_threads(par.threads);
    if (n == 0) return;
    ProgressCounter counter(par.progress, long(n));
    const std::size_t grain = std::max<std::size_t>(1, par.grain);
    in_arena(par.threads, [&] {
        tbb::task_group_context ctx;
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, n, grain),
            [&](const tbb::blocked_range<std::size_t>& r) {
                if (counter.stopped()) return;
                throw_if_stopped(par.stop);
                body(r.begin(), r.end());
                if (!counter.add(long(r.size()))) ctx.cancel_group_execution();
            },
            tbb::simple_partitioner(), ctx);
    });
    if (counter.stopped()) throw Cancelled("cancelled");
    throw_if_stopped(par.stop);
}

}  // namespace deepsea
