#pragma once
/// \file The decomposition every renderer produces (DESIGN.md section 4), in linear radiance.

#include <string>

#include "deepsea/core/image.h"

namespace deepsea {

/// Per-pixel layers of one rendered frame. final = direct + forward + backscatter.
struct Layers {
    Image final;         ///< RGB radiance
    Image direct;        ///< RGB, Lambertian signal of the lamps (D)
    Image forward;       ///< RGB, Jaffe-McGlamery forward scatter (F)
    Image backscatter;   ///< RGB, single-scattering water light along the ray (B)
    Image transmission;  ///< RGB, exp(-c d2) from the surface to the camera (0 for open water)
    Image depth;         ///< 1 channel, planar z in metres (0 for open water)
    Image normal;        ///< 3 channels, camera-frame unit normal (0 for open water)

    /// Allocates every layer at width x height (no-op when already that size).
    void resize(int width, int height);
};

/// Writes all layers to one multi-layer EXR (channels final.R, ..., depth.Z, normal.X).
/// Atomic. Throws IoError.
void write_layers(const std::string& path, const Layers& layers);

}  // namespace deepsea
