#pragma once
/// \file A sequence's output folders while it renders: created, locked against a second
/// writer, cleared of the temporaries a killed run left, removed again if nothing was written.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/batch/frame_jobs.h"
#include "deepsea/batch/sequence_manifest.h"
#include "deepsea/core/folder_lock.h"

namespace deepsea {

class OutputFolders {
public:
    /// Creates the -o and --layers folders of `files` (a sequence; frame_jobs checked them),
    /// locks each (IoError if another process writes there), and removes the temporaries
    /// that write_atomically left for `jobs`' frames or the manifest when a process that no
    /// longer runs was killed. A shard (`shard`: its index and count) shares the folders with
    /// the other shards (a shared lock, which excludes an unsharded render or a merge), locks
    /// its own part against a second run of the same shard, keeps its own manifest
    /// (shard_manifest_name) and touches only its own frames' temporaries: those of another
    /// shard, perhaps on another machine, are never taken for stale.
    OutputFolders(const FrameFiles& files, const std::vector<FrameJob>& jobs,
                  const std::optional<ShardRecord>& shard = std::nullopt);
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
    std::string m_manifest_name;
    std::vector<std::unique_ptr<FolderLock>> m_locks;
    int m_stale_removed = 0;
};

}  // namespace deepsea
