#pragma once
/// \file The decomposition every renderer produces (docs/model.md, "Image"; docs/runtime.md), in
/// linear radiance.

#include <functional>
#include <string>
#include <vector>

#include "deepsea/core/image.h"

namespace deepsea {

/// Which layers a compositor fills: all of them, or only the exposed image's (final); the
/// others are then left empty (no memory).
enum class LayerSet { All, Final };

/// Per-pixel layers of one rendered frame. final = direct + forward + backscatter (+ snow).
struct Layers {
    Image final;         ///< RGB radiance
    Image direct;        ///< RGB, Lambertian signal of the lamps (D)
    Image forward;       ///< RGB, Jaffe-McGlamery forward scatter (F)
    Image backscatter;   ///< RGB, single-scattering water light along the ray (B)
    Image transmission;  ///< RGB, exp(-c d2) from the surface to the camera (0 for open water)
    Image depth;         ///< 1 channel, planar z in metres (0 for open water)
    Image normal;        ///< 3 channels, camera-frame unit normal (0 for open water)
    /// Through a port only (else empty), 1 channel: 1 where the input shows what the pixel's
    /// water-side ray meets (a surface, or open water along its whole path), 0 where it does not
    /// (the ray leaves the input's view, or passes behind a foreground edge and finds nothing):
    /// those pixels are rendered as open water. docs/ports.md.
    Image mask;
    /// With marine snow only (else empty; docs/snow-shadows.md, "Marine snow"): the snow's radiance
    /// (RGB, also in final) and, 1 channel, the id of the particle that adds most light to each
    /// pixel (integers 1, 2, ... within the frame; 0: no particle). Ground truth for
    /// segmentation.
    Image snow;
    Image snow_id;

    /// Allocates the layers of `set` at width x height (no-op for those already that size)
    /// and frees the others.
    void resize(int width, int height, LayerSet set = LayerSet::All);
};

/// Rows of the exposed image handed over as they are finished, instead of a final layer:
/// row v's 3 x width linear RGB values, valid during the call only. Rows come from several
/// threads, each row once, in no particular order.
using FinalRows = std::function<void(int v, const float* rgb)>;

/// Every layer's name, in the order they are written: final, direct, forward, backscatter,
/// transmission, depth, normal, snow, snow_id (the last two only where marine snow is on;
/// through a port, mask after them: not in this list).
const std::vector<std::string>& layer_names();

}  // namespace deepsea
