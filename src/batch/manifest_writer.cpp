#include "manifest_writer.h"

#include <utility>

namespace deepsea {

ManifestWriter::ManifestWriter(const std::vector<std::string>& paths) {
    if (paths.empty()) return;
    m_write = [paths](const SequenceManifest& m) {
        for (const std::string& path : paths) write_manifest(path, m);
    };
    m_thread = std::thread([this] { run(); });
}

ManifestWriter::ManifestWriter(Write write) : m_write(std::move(write)) {
    if (m_write) m_thread = std::thread([this] { run(); });
}

ManifestWriter::~ManifestWriter() {
    if (!m_thread.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
    }
    m_changed.notify_all();
    m_thread.join();
}

void ManifestWriter::throw_error() {
    if (m_error) std::rethrow_exception(m_error);
}

void ManifestWriter::run() {
    std::unique_lock<std::mutex> lock(m_mutex);
    for (;;) {
        m_changed.wait(lock, [this] { return !m_busy && (m_pending || m_stop); });
        if (!m_pending) return;  // stopped, and everything posted is written
        // The newest manifest posted; frames that finish while it is written make the next.
        SequenceManifest m = std::move(*m_pending);
        m_pending.reset();
        m_busy = true;
        lock.unlock();
        std::exception_ptr error;
        try {
            m_write(m);
        } catch (...) {
            error = std::current_exception();
        }
        lock.lock();
        m_busy = false;
        if (error && !m_error) m_error = error;
        m_changed.notify_all();
    }
}

void ManifestWriter::write_now(const SequenceManifest& m) {
    if (!m_write) return;
    {
        std::unique_lock<std::mutex> lock(m_mutex);
        // After what was posted: a manifest on disk never goes back to fewer frames.
        m_changed.wait(lock, [this] { return !m_pending && !m_busy; });
        throw_error();
        m_busy = true;
    }
    std::exception_ptr error;
    try {
        m_write(m);
    } catch (...) {
        error = std::current_exception();
    }
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_busy = false;
    }
    m_changed.notify_all();
    if (error) std::rethrow_exception(error);
}

void ManifestWriter::post(const SequenceManifest& m) {
    if (!m_write) return;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        throw_error();
        if (m_pending) {
            *m_pending = m;  // reuses the strings' storage
        } else {
            m_pending = m;
        }
    }
    m_changed.notify_all();
}

}  // namespace deepsea
