#pragma once
/// \file Which frames a render reads and where each one's outputs go: one frame, or every
/// colour / depth pair of two glob patterns. The one place that finds and pairs frame files.

#include <string>
#include <vector>

namespace deepsea {

/// One frame's files: inputs and where its outputs go (an empty path is not written).
struct FrameJob {
    std::string rgb, depth;
    std::string output;  ///< exposed image (PNG/JPEG/EXR)
    std::string layers;  ///< multi-layer EXR
};

/// What the user named: colour and depth inputs (files or quoted glob patterns such as
/// 'dir/*.png') and the outputs (files for one frame, folders for a sequence; empty: none).
struct FrameFiles {
    std::string rgb, depth;
    std::string output, layers;
};

/// True if `path` holds a glob character (*, ? or [).
bool is_pattern(const std::string& path);

/// One job if rgb is a plain file (then depth must be one too, ConfigError otherwise); for a
/// pattern, the pairs of pair_frames with outputs <output>/<colour stem>.png and
/// <layers>/<colour stem>.exr, the folders created (IoError if they cannot be).
std::vector<FrameJob> frame_jobs(const FrameFiles& files);

/// Pairs colour and depth files by position: both lists sorted, files in both lists dropped
/// from the colour list; InputError when the counts differ or a list is empty (naming the
/// patterns).
std::vector<FrameJob> pair_frames(std::vector<std::string> rgb, std::vector<std::string> depth,
                                  const std::string& rgb_pattern, const std::string& depth_pattern);

/// Files matching a shell glob pattern, sorted (empty if none).
std::vector<std::string> glob_files(const std::string& pattern);

}  // namespace deepsea
