#pragma once
/// \file One writer per output folder: an exclusive, non-blocking lock on a hidden file in it.

#include <string>

namespace deepsea {

/// Holds an exclusive flock(2) on `<folder>/.deepsea.lock` from construction to destruction.
/// The kernel drops the lock when the process ends, even by SIGKILL, so a stale lock file
/// never blocks a later run. The lock file holds the owner's process id for the message and
/// is removed when the lock is released normally.
class FolderLock {
public:
    /// Throws IoError naming the folder when another process holds the lock (with its process
    /// id) or the lock file cannot be created. The folder must exist.
    explicit FolderLock(const std::string& folder);
    ~FolderLock();
    FolderLock(const FolderLock&) = delete;
    FolderLock& operator=(const FolderLock&) = delete;

    /// The lock file's name inside the folder.
    static const char* file_name() { return ".deepsea.lock"; }

private:
    std::string m_path;
    int m_fd = -1;
};

}  // namespace deepsea
