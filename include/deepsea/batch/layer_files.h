#pragma once
/// \file Layer files: which layers a `--layers` EXR holds, and writing them.

#include <string>
#include <vector>

#include "deepsea/camera/camera_stage.h"
#include "deepsea/io/image_io.h"
#include "deepsea/runtime/layers.h"

namespace deepsea {

/// The camera stage's layers a `--layers` file can hold (CameraOutput's raw, linear_dn and
/// noise_free), after the renderer's layer_names().
const std::vector<std::string>& camera_layer_names();

/// Every layer a `--layers` file can hold: layer_names(), then with a camera stage
/// camera_layer_names().
std::vector<std::string> all_layer_names(bool camera);

/// Which layers a `--layers` file holds, and in what precision.
struct LayerOutput {
    /// A subset of all_layer_names(camera), in its order.
    std::vector<std::string> names = layer_names();
    bool half = false;    ///< half floats instead of float
    bool camera = false;  ///< a camera stage records the frames (its layers may be named)

    bool all() const { return names == all_layer_names(camera); }
    /// The compositor's LayerSet that fills these layers: Final when only final is wanted
    /// (the others are then not computed).
    LayerSet compositor_set() const;
    /// The camera stage's layers among these.
    CameraLayerSet camera_set() const;
    /// "all" or the names joined by commas, as the sequence manifest records them.
    std::string describe() const;
};

/// Parses `--layer-set`: comma-separated layer names ("all" for every layer), any order, each
/// once; the result is in all_layer_names(camera)'s order. ConfigError naming the unknown or
/// repeated name (and listing the known ones), or a camera layer without a camera stage.
std::vector<std::string> parse_layer_set(const std::string& list, bool camera = false);

/// Writes the layers `out` names to one multi-layer EXR (channels final.R, ..., depth.Z,
/// normal.X, with every layer and a port's mask mask.Y, then the camera's raw.R, ...: from
/// `camera`, which must hold them), float or half,
/// PIZ-compressed, with `meta` in its header. Atomic. Throws IoError.
void write_layers(const std::string& path, const Layers& layers, const ImageMetadata& meta = {},
                  const LayerOutput& out = {}, const CameraOutput* camera = nullptr);

}  // namespace deepsea
