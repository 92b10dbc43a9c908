#pragma once
/// \file Exact per-pixel rendering without an asset: the ground truth that every faster path
/// is checked against. Slow by design: the backscatter integral is evaluated for every pixel.

#include <optional>

#include "deepsea/core/image.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/port.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/layers.h"

namespace deepsea {

struct ReferenceOptions {
    Quadrature quadrature;
    /// Open-water rays end at this planar depth in metres (e.g. an asset's z_max to compare
    /// with it). 0: integrate until the transmission along the ray is negligible (1e-9).
    double open_water_z = 0.0;
    /// The housing's port (docs/port-bake.md, "The exact reference through a port"): every pixel
    /// along its water-side ray (trace_port, the green channel's), its surface where that ray
    /// meets the depth map (find_port_hit, the runtime's hit definition in double). The layers
    /// stay water-side radiance, as the renderer's, with the mask; radiance_at_camera gives
    /// what reaches the camera. Checked before any pixel (validate, check_port_view,
    /// check_port_sees_input).
    std::optional<Port> port;
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

/// The radiance that reaches the camera in air from water-side radiance `image` (RGB, the
/// camera's size) seen through `port`: each pixel times port_radiance_factor of its own ray
/// (the n^2 law, and Fresnel where the port asks), as the camera stage applies it.
Image radiance_at_camera(const Image& image, const Port& port, const Camera& camera);

}  // namespace deepsea
