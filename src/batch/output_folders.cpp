#include "deepsea/batch/output_folders.h"

#include <signal.h>

#include <cerrno>
#include <filesystem>
#include <set>

#include "deepsea/batch/sequence_manifest.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

bool process_alive(long pid) { return ::kill(pid_t(pid), 0) == 0 || errno == EPERM; }

}  // namespace

OutputFolders::OutputFolders(const FrameFiles& files, const std::vector<FrameJob>& jobs,
                             const std::optional<ShardRecord>& shard)
    : m_manifest_name(shard ? shard_manifest_name(shard->index, shard->count) : kManifestName) {
    for (const std::string& dir : {files.output, files.layers}) {
        if (dir.empty()) continue;
        std::error_code ec;
        if (!m_folders.empty() && fs::equivalent(m_folders.front(), dir, ec)) continue;
        const bool existed = fs::exists(dir, ec);
        fs::create_directories(dir, ec);
        if (ec || !fs::is_directory(dir)) {
            throw IoError(dir + ": cannot create the output folder" +
                          (ec ? ": " + ec.message() : std::string()));
        }
        if (!existed) m_created.push_back(dir);
        m_folders.push_back(dir);
        if (!shard) {
            m_locks.push_back(std::make_unique<FolderLock>(dir));
            continue;
        }
        m_locks.push_back(std::make_unique<FolderLock>(dir, FolderLock::Mode::Shared));
        // ".deepsea-sequence.shard-0003-of-0004.lock"
        const std::string name =
            "." + m_manifest_name.substr(0, m_manifest_name.size() - 4) + "lock";
        m_locks.push_back(std::make_unique<FolderLock>(dir, FolderLock::Mode::Exclusive, name));
    }
    // Only names this sequence writes, and only from writers that are gone: holding the lock,
    // no other render writes here; a live process's temporary is never touched.
    std::set<std::string> ours{m_manifest_name};
    for (const FrameJob& j : jobs) {
        for (const std::string& out : {j.output, j.layers}) {
            if (!out.empty()) ours.insert(temporary_key(fs::path(out).filename().string()));
        }
    }
    for (const std::string& dir : m_folders) {
        for (const auto& entry : fs::directory_iterator(dir)) {
            const auto tmp = parse_temporary_name(entry.path().filename().string());
            if (!tmp || !ours.count(tmp->target) || process_alive(tmp->pid)) continue;
            std::error_code ec;
            if (fs::remove(entry.path(), ec)) ++m_stale_removed;
        }
    }
}

OutputFolders::~OutputFolders() {
    m_locks.clear();
    for (const std::string& dir : m_created) {
        std::error_code ec;
        if (fs::is_empty(dir, ec)) fs::remove(dir, ec);
    }
}

std::vector<std::string> OutputFolders::manifests() const {
    std::vector<std::string> out;
    for (const std::string& dir : m_folders)
        out.push_back((fs::path(dir) / m_manifest_name).string());
    return out;
}

}  // namespace deepsea
