#pragma once
/// \file The decomposition every renderer produces (docs/model.md, "Image"; docs/runtime.md), in
/// linear radiance.

#include <string>
#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/io/image_io.h"

namespace deepsea {

/// Which layers a compositor fills: all of them, or only the exposed image's (final); the
/// others are then left empty (no memory).
enum class LayerSet { All, Final };

/// Per-pixel layers of one rendered frame. final = direct + forward + backscatter.
struct Layers {
    Image final;         ///< RGB radiance
    Image direct;        ///< RGB, Lambertian signal of the lamps (D)
    Image forward;       ///< RGB, Jaffe-McGlamery forward scatter (F)
    Image backscatter;   ///< RGB, single-scattering water light along the ray (B)
    Image transmission;  ///< RGB, exp(-c d2) from the surface to the camera (0 for open water)
    Image depth;         ///< 1 channel, planar z in metres (0 for open water)
    Image normal;        ///< 3 channels, camera-frame unit normal (0 for open water)

    /// Allocates the layers of `set` at width x height (no-op for those already that size)
    /// and frees the others.
    void resize(int width, int height, LayerSet set = LayerSet::All);
};

/// Every layer's name, in the order they are written: final, direct, forward, backscatter,
/// transmission, depth, normal.
const std::vector<std::string>& layer_names();

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
