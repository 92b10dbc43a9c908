#pragma once
// Internal to batch: keeps a sequence's manifests up to date from a thread of its own, so that
// their write and fsync (about 1 ms median, up to 40 ms, in `strace -f -T` of 32-frame
// renders of the authors' frames on this project's machine) never hold the pipeline's lock
// nor a pipeline thread (docs/sequences.md, "The manifest").

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "deepsea/batch/sequence_manifest.h"

namespace deepsea {

/// One writer per sequence. Its thread writes the newest manifest it was given; frames that
/// finish while a write is in flight are all covered by the next write (coalescing), so a
/// manifest on disk is never newer than the frames written and never more than one write
/// behind them. Every write is whole (write_manifest: a temporary, fsync, rename).
///
/// Why a thread of its own and not every N frames or T ms: the fsync blocks in the kernel
/// without using a core, so a thread outside TBB's arena keeps both pipeline threads reading
/// and compositing, the manifest lags the frames by one write at most (whatever the frame
/// rate), and a render of any length needs no tuning.
class ManifestWriter {
public:
    /// Writes one manifest wherever it belongs (each output folder); may throw.
    using Write = std::function<void(const SequenceManifest&)>;

    /// `paths`: the manifest files (each output folder's); none: every call does nothing and
    /// no thread is started.
    explicit ManifestWriter(const std::vector<std::string>& paths);
    /// `write` instead of files (tests).
    explicit ManifestWriter(Write write);
    /// Writes what was posted and not yet written (errors are dropped: a render that ends in
    /// an exception reports that one), then ends the thread.
    ~ManifestWriter();
    ManifestWriter(const ManifestWriter&) = delete;
    ManifestWriter& operator=(const ManifestWriter&) = delete;

    /// Writes `m` on the caller's thread and returns once it is on disk, after the write in
    /// flight and those posted (which `m` must be at least as new as). The first manifest of
    /// a render, which must hold the exposure before any frame is written, goes this way.
    /// Throws the write's error, or an earlier write's.
    void write_now(const SequenceManifest& m);

    /// Hands `m` to the thread and returns at once (a copy: the caller may change its own).
    /// It replaces a manifest posted and not yet written. Throws an earlier write's error, so
    /// that a manifest that cannot be written stops the render, one frame later than it fails.
    void post(const SequenceManifest& m);

private:
    void run();
    void throw_error();  // with m_mutex held

    Write m_write;
    std::mutex m_mutex;
    std::condition_variable m_changed;  // pending, busy or stop changed
    std::optional<SequenceManifest> m_pending;
    bool m_busy = false;  // a write is in flight (the thread's or write_now's)
    bool m_stop = false;
    std::exception_ptr m_error;  // the first write that failed
    std::thread m_thread;        // last: started once the members above exist
};

}  // namespace deepsea
