#pragma once
/// \file Rendering frames and whole sequences with a loaded asset: a TBB pipeline in which
/// reading, compositing and writing overlap; the asset is loaded once by the caller.

#include <functional>
#include <string>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/camera.h"
#include "deepsea/runtime/exposure.h"

namespace deepsea {

/// One frame's files: inputs and where its outputs go (an empty path is not written).
struct FrameJob {
    std::string rgb, depth;
    std::string output;  ///< exposed image (PNG/JPEG/EXR)
    std::string layers;  ///< multi-layer EXR
};

struct SequenceOptions {
    DepthReadOptions depth_read;
    DepthKind depth_kind = DepthKind::Z;
    Exposure exposure;          ///< auto: chosen on the first frame, then kept (no flicker)
    bool forward = true;        ///< forward scatter, if the asset's water defines it
    bool resume = false;        ///< skip frames whose `output` (or `layers`) already exists
    int bits = 8;               ///< PNG bit depth
    /// The frames' camera; unset (width 0): the asset's camera, resampled to the frame size.
    Camera camera;
    /// Called after each frame, in order: (frames done, total).
    std::function<void(int, int)> progress;
};

struct SequenceResult {
    int written = 0;
    int skipped = 0;                  ///< --resume
    std::vector<std::string> errors;  ///< one line per failed frame
    double seconds = 0.0;
    double exposure = 0.0;            ///< the factor used
};

/// Renders every job; a frame that cannot be read or written is reported in `errors` and
/// skipped, the rest are written. Throws only for problems that stop every frame (e.g. the
/// asset does not fit the frames' camera).
SequenceResult render_sequence(const Asset& asset, const std::vector<FrameJob>& jobs,
                               const SequenceOptions& opt);

/// Pairs colour and depth files: both lists sorted; InputError when the counts differ or a
/// list is empty (naming the patterns).
std::vector<FrameJob> pair_frames(std::vector<std::string> rgb, std::vector<std::string> depth,
                                  const std::string& rgb_pattern,
                                  const std::string& depth_pattern);

/// Files matching a shell glob pattern, sorted (empty if none).
std::vector<std::string> glob_files(const std::string& pattern);

}  // namespace deepsea
