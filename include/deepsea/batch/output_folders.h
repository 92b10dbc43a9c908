#pragma once
/// \file A sequence's output folders while it renders: created, locked against a second
/// writer, cleared of the temporaries a killed run left, removed again if nothing was written.

#include <memory>
#include <string>
#include <vector>

#include "deepsea/batch/frame_jobs.h"
#include "deepsea/core/folder_lock.h"

namespace deepsea {

class OutputFolders {
public:
    /// Creates the -o and --layers folders of `files` (a sequence; frame_jobs checked them),
    /// locks each (IoError if another process writes there), and removes the temporaries
    /// that write_atomically left for this sequence's frames or manifest when a process that
    /// no longer runs was killed.
    OutputFolders(const FrameFiles& files, const std::vector<FrameJob>& jobs);
    /// Releases the locks; a folder this object created and that is still empty is removed.
    ~OutputFolders();
    OutputFolders(const OutputFolders&) = delete;
    OutputFolders& operator=(const OutputFolders&) = delete;

    /// The manifest path in each folder.
    std::vector<std::string> manifests() const;
    /// How many stale temporaries were removed.
    int stale_removed() const { return m_stale_removed; }

private:
    std::vector<std::string> m_folders, m_created;
    std::vector<std::unique_ptr<FolderLock>> m_locks;
    int m_stale_removed = 0;
};

}  // namespace deepsea
