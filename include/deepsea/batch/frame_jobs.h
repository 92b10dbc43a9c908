#pragma once
/// \file Which frames a render reads and where each one's outputs go: one frame, or every
/// colour / depth pair of two glob patterns. The one place that finds, pairs and checks frame
/// files, before any work and without creating anything.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/optics/camera_motion.h"

namespace deepsea {

/// One frame's files: inputs and where its outputs go (an empty path is not written).
struct FrameJob {
    std::string rgb, depth;
    std::string output;  ///< exposed image (PNG/JPEG/TIFF/EXR)
    std::string layers;  ///< multi-layer EXR
    /// The camera's pose (camera to world), where known: marine snow stays fixed in the world.
    std::optional<CameraPose> pose;
    /// The camera's poses when the shutter opens and closes, for marine snow's motion streaks
    /// (frame_poses.h); unset: none.
    std::optional<Shutter> shutter;
};

/// The frame's key for a camera's noise (camera_stage.h): FNV-1a (core/hash.h) of the colour
/// file's stem, so that a frame gets the same noise rendered alone, in a sequence, on any shard,
/// in any order, and two frames of a sequence (distinct stems) get different noise.
std::uint64_t frame_key(const FrameJob& job);

/// What the user named: colour and depth inputs (files or quoted glob patterns such as
/// 'dir/*.png') and the outputs (files for one frame, folders for a sequence; empty: none).
struct FrameFiles {
    std::string rgb, depth;
    std::string output, layers;
    /// The exposed images' format, as an extension without the dot: png, jpg, tif or exr.
    /// Empty: png for a sequence, -o's own extension for one frame (which it must match when
    /// given).
    std::string format;
    /// A sequence: the colour input is a pattern (then outputs are folders).
    bool sequence() const;
};

/// True if `path` holds a glob character (*, ? or [) or, unless it names an existing file, a
/// frame-number token: `%04d`, `%d` or a run of '#' (`####`), digits as printf writes them
/// (at least that many: `%04d` and `####` match 0007 and 12345).
bool is_pattern(const std::string& path);

/// The jobs of a render, checked before anything is read, composited or created:
/// - one frame (rgb a plain file): depth must be one too (ConfigError); -o needs an extension
///   OpenImageIO writes and --layers `.exr` (ConfigError), their folders must exist and be
///   writable (IoError);
/// - a sequence: the pairs of pair_frames, outputs <output>/<colour stem>.<format> and
///   <layers>/<colour stem>.exr; -o and --layers must be folders or creatable as such
///   (ConfigError for an existing file or an image file name, IoError for an unwritable
///   place), never a folder that holds inputs;
/// - always: something to write, no output the same file as an input or as another output
///   (ConfigError naming both), a known format (ConfigError).
std::vector<FrameJob> frame_jobs(const FrameFiles& files);

/// Pairs colour and depth files by frame identity. A file's frame key is its stem less the
/// fixed text around the wildcards of its pattern's file name ('*_depth.exr': the stem less
/// "_depth"), or else the last number in its stem (0001 = 1): the first of these that pairs
/// every file is used. Files caught by both patterns are dropped from the colour list. Jobs in
/// colour-file order. InputError, before any work, for an empty list, two files of one list
/// with the same key, or files without a partner (listing them).
std::vector<FrameJob> pair_frames(std::vector<std::string> rgb, std::vector<std::string> depth,
                                  const std::string& rgb_pattern, const std::string& depth_pattern);

/// Files matching a shell glob pattern, frame-number tokens included (is_pattern), sorted
/// (empty if none).
std::vector<std::string> glob_files(const std::string& pattern);

}  // namespace deepsea
