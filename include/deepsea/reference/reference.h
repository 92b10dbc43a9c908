#pragma once
/// \file Exact per-pixel rendering without an asset: the ground truth that every faster path
/// is checked against. Slow by design: the backscatter integral is evaluated for every pixel.

#include "deepsea/core/image.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/layers.h"

namespace deepsea {

struct ReferenceOptions {
    Quadrature quadrature;
    /// Open-water rays end at this planar depth in metres (e.g. an asset's z_max to compare
    /// with it). 0: integrate until the transmission along the ray is negligible (1e-9).
    double open_water_z = 0.0;
};

/// Planar depth at which open-water rays end for this water and options.
double open_water_depth(const Water& water, const ReferenceOptions& opt);

/// Renders direct, forward, backscatter, transmission, depth and normal layers exactly.
/// rgb: linear albedo, 3 channels; zdepth: planar depth in metres, 1 channel, same size as rgb
/// and as the camera (InputError otherwise). Non-finite or <= 0 depth is open water.
/// Runs on par.threads workers; par.progress is called per image row (false cancels).
Layers render_reference(const Camera& camera, const Rig& rig, const Water& water, const Image& rgb,
                        const Image& zdepth, const ReferenceOptions& opt = {},
                        const Parallel& par = {});

}  // namespace deepsea
