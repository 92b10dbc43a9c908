#pragma once
/// \file Joining the shards of a sequence render (docs/sequences.md, "Shards"): every shard
/// renders part of the frames into the same folders and keeps its own manifest; once all are
/// done, one command checks that they agree and that every frame is there, and writes the
/// sequence's manifest, the same as an unsharded render's.

#include <string>

#include "deepsea/batch/sequence_manifest.h"

namespace deepsea {

struct ShardMerge {
    int shards = 0;           ///< shard manifests found (all of them: 0 .. count - 1)
    int frames = 0;           ///< frames of the sequence, each with its outputs here
    std::string manifest;     ///< the merged manifest's path (written unless check_only)
    SequenceManifest merged;  ///< its content: the shards' record, less the shard
};

/// Checks the shard manifests in the output folder `folder` (shard_manifest_name) and the
/// frames there, holding the folder's lock (IoError while a shard still renders into it):
/// - all shards of one count are there, each finished (FramesFailed, exit 6: which
///   shards to render or resume);
/// - they agree on everything but their part (ConfigError naming two shards and the first key
///   that differs, such as exposure.factor);
/// - the recorded inputs still pair into as many frames, and each frame's outputs in this
///   folder are there, non-empty and not cut short (FramesFailed, listing them).
/// Then, unless `check_only`, writes `<folder>/deepsea-sequence.json` atomically (refusing a
/// folder whose manifest records other inputs) and removes the shard manifests.
ShardMerge merge_shards(const std::string& folder, bool check_only);

}  // namespace deepsea
