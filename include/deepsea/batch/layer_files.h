#pragma once
/// \file Layer files: which layers a `--layers` EXR holds, and writing them.

#include <string>
#include <vector>

#include "deepsea/io/image_io.h"
#include "deepsea/runtime/layers.h"

namespace deepsea {

/// Which layers a `--layers` file holds, and in what precision.
struct LayerOutput {
    std::vector<std::string> names = layer_names();  ///< a subset of layer_names(), in its order
    bool half = false;                               ///< half floats instead of float

    bool all() const { return names == layer_names(); }
    /// The compositor's LayerSet that fills these layers: Final when only final is wanted
    /// (the others are then not computed).
    LayerSet compositor_set() const;
    /// "all" or the names joined by commas, as the sequence manifest records them.
    std::string describe() const;
};

/// Parses `--layer-set`: comma-separated layer names ("all" for every layer), any order, each
/// once; the result is in layer_names()'s order. ConfigError naming the unknown or repeated
/// name (and listing the known ones) otherwise.
std::vector<std::string> parse_layer_set(const std::string& list);

/// Writes the layers `out` names to one multi-layer EXR (channels final.R, ..., depth.Z,
/// normal.X), float or half, PIZ-compressed, with `meta` in its header. Atomic. Throws
/// IoError.
void write_layers(const std::string& path, const Layers& layers, const ImageMetadata& meta = {},
                  const LayerOutput& out = {});

}  // namespace deepsea
