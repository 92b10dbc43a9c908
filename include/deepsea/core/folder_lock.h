#pragma once
/// \file One writer per output folder: an exclusive, non-blocking lock on a hidden file in it.

#include <string>

namespace deepsea {

/// Holds a flock(2) on `<folder>/.deepsea.lock` (or another hidden name) from construction to
/// destruction. The kernel drops the lock when the process ends, even by SIGKILL, so a stale
/// lock file never blocks a later run. An exclusive lock's file holds the owner's process id
/// for the message; the file is removed when the last holder releases the lock normally.
class FolderLock {
public:
    /// Exclusive: the only writer (a render, a merge of shards). Shared: one of several writers
    /// that write disjoint files (the shards of a render), which exclude an exclusive writer.
    enum class Mode { Exclusive, Shared };

    /// Throws IoError naming the folder when another process holds the lock (with its process
    /// id) or the lock file cannot be created. The folder must exist.
    explicit FolderLock(const std::string& folder, Mode mode = Mode::Exclusive,
                        const std::string& name = file_name());
    ~FolderLock();
    FolderLock(const FolderLock&) = delete;
    FolderLock& operator=(const FolderLock&) = delete;

    /// The lock file's name inside the folder.
    static const char* file_name() { return ".deepsea.lock"; }

private:
    std::string m_path;
    int m_fd = -1;
    Mode m_mode;
};

}  // namespace deepsea
