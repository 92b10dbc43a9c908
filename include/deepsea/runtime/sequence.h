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
#include "deepsea/runtime/frame_jobs.h"

namespace deepsea {

struct SequenceOptions {
    DepthReadOptions depth_read;
    DepthKind depth_kind = DepthKind::Z;
    Exposure exposure;    ///< auto: chosen on the first frame, then kept (no flicker)
    bool forward = true;  ///< forward scatter, if the asset's water defines it
    bool resume = false;  ///< skip frames whose `output` (or `layers`) already exists
    int bits = 8;         ///< PNG bit depth
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
    double exposure = 0.0;  ///< the factor used
};

/// Renders every job; a frame that cannot be read or written is reported in `errors` and
/// skipped, the rest are written. Throws only for problems that stop every frame (e.g. the
/// asset does not fit the frames' camera).
SequenceResult render_sequence(const Asset& asset, const std::vector<FrameJob>& jobs,
                               const SequenceOptions& opt);

}  // namespace deepsea
