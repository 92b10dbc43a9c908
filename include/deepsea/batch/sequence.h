#pragma once
/// \file Rendering frames and whole sequences with a loaded asset: a TBB pipeline in which
/// reading, compositing and writing overlap; the asset is loaded once by the caller.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/batch/frame_jobs.h"
#include "deepsea/batch/layer_files.h"
#include "deepsea/batch/sequence_manifest.h"
#include "deepsea/camera/camera_stage.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/port.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/lamp_shadows.h"
#include "deepsea/runtime/marine_snow.h"

namespace deepsea {

struct SequenceOptions {
    DepthReadOptions depth_read;
    DepthKind depth_kind = DepthKind::Z;
    Exposure exposure;     ///< auto: chosen on the first frame composited, then kept (no flicker)
    bool forward = true;   ///< forward scatter, if the asset's water defines it
    bool shadows = false;  ///< lamp shadows from the depth map (docs/model.md)
    int shadow_step = kDefaultShadowStep;  ///< their sweep's step (ShadowSettings::step)
    /// Marine snow (docs/model.md): unset, none. Each frame's key is frame_key(job), its pose
    /// the job's.
    std::optional<SnowSettings> snow;
    /// Skip frames whose outputs are complete (non-empty and decoding fully); with manifests,
    /// continue the sequence they record (its exposure) or refuse (check_resumable).
    bool resume = false;
    int bits = 8;  ///< PNG bit depth
    /// What the --layers files hold (which layers, half or float).
    LayerOutput layer_output;
    /// The frames' camera; unset (width 0): the asset's camera, resampled to the frame size.
    Camera camera;
    /// The camera stage (docs/camera.md): each frame's radiance is recorded by this camera
    /// (lens, sensor, processing) over the frames' camera, with frame_key(job) as its noise's
    /// frame key; the image is its display values and `exposure` is not used. Its layers
    /// (raw, linear_dn, noise_free) may be named in layer_output (whose `camera` must then be
    /// true). Unset: the image is the radiance times the exposure factor.
    std::optional<CameraModel> camera_model;
    /// The housing's port (docs/ports.md): every pixel sees along its water-side ray; the
    /// layer files gain `mask`; the manifest records it (a resume with another port is refused).
    std::optional<Port> port;
    /// Called with (0, total) first and after each frame, in order, with (frames done, total);
    /// false stops the sequence once the frames in flight are finished (SequenceResult::
    /// interrupted).
    Progress progress;
    /// Called for each frame written (`skipped` false) or skipped by --resume (true), in the
    /// order they finish, one at a time: for a line per frame. May be empty.
    std::function<void(const FrameJob& job, bool skipped)> on_frame;
    /// deepsea's version: recorded in the manifest and in every output's metadata.
    std::string version;
    /// A sequence into folders: the manifest path in each output folder (OutputFolders::
    /// manifests) and the input patterns it records. Empty: no manifest (one frame, tools).
    std::vector<std::string> manifests;
    std::string rgb_pattern, depth_pattern;
    /// A shard of a sequence (`jobs` are its frames): recorded in its manifests.
    std::optional<ShardRecord> shard;
    /// Auto exposure: the frame to choose it on, composited first, before any job (a shard's:
    /// the sequence's first frame, so that every shard chooses the same factor). Unset: the
    /// first job composited. Not used when a manifest being resumed holds the exposure.
    std::optional<FrameJob> exposure_frame;
};

struct SequenceResult {
    int total = 0;                    ///< jobs given
    int written = 0;                  ///< frames rendered and written by this run
    int skipped = 0;                  ///< --resume: frames whose outputs were complete
    std::vector<std::string> errors;  ///< one line per failed frame
    std::vector<int> error_codes;     ///< each error's exit code (Error::exit_code of its kind)
    bool interrupted = false;         ///< progress said stop before every frame was done
    double seconds = 0.0;
    double exposure = 0.0;  ///< the factor used (0 if no frame was composited or kept)
    /// With a camera stage: the last frame's exposure time and gain (0 before any frame).
    FrameExposure camera_exposure;
};

/// The metadata every output of a render carries: deepsea:exposure (the factor, %.17g),
/// deepsea:asset_hash and, if known, deepsea:version.
ImageMetadata output_metadata(const Asset& asset, double exposure, const std::string& version);

/// The metadata a frame recorded by a camera stage adds (docs/camera.md): deepsea:frame_key,
/// deepsea:exposure_time_ms, deepsea:system_gain and deepsea:white_balance (three gains).
ImageMetadata camera_metadata(const CameraOutput& recorded, std::uint64_t frame_key);

/// Renders every job; a frame that cannot be read or written is reported in `errors` and
/// skipped, the rest are written. With manifests, reads them first (check_same_inputs, and
/// check_resumable with --resume, whose exposure it keeps), writes them once the exposure is
/// known, before the first output, as frames finish (from a thread of their own, outside the
/// pipeline's lock: frames that finish during a write are counted by the next,
/// docs/sequences.md) and at the end, counting every frame. Throws only for problems that
/// stop every frame: the asset does not fit the first frame's camera (AssetError naming the
/// frame; a later frame that does not fit fails alone), a manifest refuses the run, or --resume
/// finds frames but no manifest to take their exposure from, or the exposure_frame fails (its
/// error, naming it).
SequenceResult render_sequence(const Asset& asset, const std::vector<FrameJob>& jobs,
                               const SequenceOptions& opt);

}  // namespace deepsea
