#pragma once
/// \file The manifest a sequence render keeps beside its frames (docs/sequences.md): what
/// made them (asset, camera, settings, deepsea version), the exposure they share and how many
/// are done, so that `--resume` continues the same sequence or refuses.

#include <optional>
#include <string>
#include <vector>

#include "deepsea/batch/frame_jobs.h"
#include "deepsea/optics/camera.h"

namespace deepsea {

/// The manifest's file name in each output folder.
inline constexpr const char* kManifestName = "deepsea-sequence.json";

/// A shard's manifest's name: `deepsea-sequence.shard-0003-of-0004.json` for shard 3 of 4.
std::string shard_manifest_name(int index, int count);

/// What a shard's manifest adds (docs/sequences.md, "Shards"): which shard, of how many frames
/// in all, and the sequence's output folders (absolute), so that merge_shards knows which
/// outputs a folder holds.
struct ShardRecord {
    int index = 0, count = 1;
    int sequence_frames = 0;  ///< frames of the whole sequence (the shard's: frames_total)
    std::string image_folder, layers_folder;  ///< -o and --layers, absolute; empty: none
};

/// One sequence's record. JSON keys in docs/sequences.md.
struct SequenceManifest {
    static constexpr int kFormat = 1;  ///< version of this JSON layout
    std::string deepsea_version;
    std::string asset_hash;  ///< the asset's input hash (BakeInfo::input_hash)
    std::string rgb, depth;  ///< input patterns, absolute
    Camera camera;           ///< the frames' camera as given (--camera), or the asset's
    /// The camera stage that records the frames, as the setup YAML's camera section
    /// (setup_to_yaml); empty: none, the exposure factor makes the image.
    std::string camera_stage;
    /// The housing's port, as the setup YAML's camera section with its port (setup_to_yaml);
    /// empty: none (the key "port" holds "none").
    std::string port;
    bool auto_exposure = true;  ///< without a camera stage: auto or a fixed factor
    double percentile = 0, target = 0, max_clipped = 0;  ///< auto exposure's settings
    double exposure = 0;               ///< the factor every frame uses; 0 until chosen
    std::string exposure_frame;        ///< auto: the colour file it was chosen on
    bool image = false;                ///< exposed images are written (-o)
    std::string image_format = "png";  ///< their format (--format): png, jpg, tif or exr
    int bits = 8;                      ///< their bit depth
    bool layers = false;               ///< layer EXRs are written (--layers)
    std::string layer_set = "all";     ///< with layers: "all" or the names joined by commas
    bool half = false;                 ///< half-float layers (--half)
    bool forward = true;               ///< forward scatter on
    bool shadows = false;              ///< lamp shadows on (absent from older manifests: off)
    int shadow_step = 2;  ///< with shadows, their sweep's step (absent: the default, 2)
    /// Marine snow: its preset ("off": none; absent from older manifests: off), the seed of
    /// its particles and the lens's focus distance (metres).
    std::string snow = "off";
    std::uint64_t snow_seed = 0;
    double focus_distance_m = 0;
    /// The snow's values by their setup keys (concentration, d_min_mm, ...), so
    /// that a custom snow is compared too; empty in older manifests (not compared).
    std::vector<std::pair<std::string, double>> snow_values;
    /// The frames' camera poses (render --poses), "fnv1a64:<16 hex>" of every frame's pose in
    /// frame order (poses_hash), and how many frames have one; empty and 0: none (and in
    /// manifests from before poses were recorded).
    std::string poses_hash;
    int poses = 0;
    std::string depth_kind = "z", depth_channel;
    double depth_scale = 0.001;
    int frames_total = 0;
    int frames_done = 0;               ///< frames whose outputs were complete at the last update
    std::optional<ShardRecord> shard;  ///< a shard's manifest; none: the whole sequence's
};

/// "fnv1a64:<16 hex>" of the poses of `jobs` in order (each frame's camera centre and axes as
/// doubles, then its shutter's poses where it has them; a frame without one hashes a marker),
/// or empty if no frame has a pose.
std::string poses_hash(const std::vector<FrameJob>& jobs);

/// The manifest as pretty-printed JSON (doubles round-trip exactly).
std::string manifest_to_json(const SequenceManifest& m);

/// Parses manifest_to_json's text; InputError "<path>: <key>: <problem>" for malformed JSON, a
/// missing key, a wrong type or an unknown format.
SequenceManifest manifest_from_json(const std::string& json, const std::string& path);

/// Reads a manifest file (IoError if unreadable, InputError as manifest_from_json).
SequenceManifest read_manifest(const std::string& path);

/// Writes it atomically.
void write_manifest(const std::string& path, const SequenceManifest& m);

/// ConfigError naming `path` unless `run` reads the same inputs as the folder's manifest:
/// frames of another sequence are never overwritten.
void check_same_inputs(const SequenceManifest& folder, const SequenceManifest& run,
                       const std::string& path);

/// The first key (dotted, "exposure.factor") whose value differs between the two manifests'
/// JSON, with both values ("exposure.factor: 160.1 vs 160.2"); empty if they are the same.
/// Keys in `ignore` (top level: "shard", "frames") are not compared.
std::string first_difference(const SequenceManifest& a, const SequenceManifest& b,
                             const std::vector<std::string>& ignore);

/// ConfigError naming `path` and the first difference unless `run` would render frames
/// identical to the folder's: same deepsea version, asset, camera, exposure rule, outputs and
/// settings (the exposure factor itself is kept from the folder).
void check_resumable(const SequenceManifest& folder, const SequenceManifest& run,
                     const std::string& path);

}  // namespace deepsea
