#pragma once
/// \file Procedural RGB-D seafloor flights: the project's embedded demo input and test source.

#include <cstdint>

#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"

namespace deepsea {

/// A camera flying a straight path over a procedural seafloor.
struct FlightParams {
    Camera camera;             ///< intrinsics of the rendered frames
    int frames = 8;
    double altitude = 3.0;     ///< metres above the mean seafloor
    double speed = 0.25;       ///< metres travelled per frame (along +x of the seafloor)
    double pitch_deg = 0.0;    ///< 0: looking straight down; > 0 tilts the view forward
    std::uint64_t seed = 1;    ///< same seed, same seafloor, bit for bit
};

/// One rendered frame: linear RGB albedo (3 channels) and planar z-depth in metres (1 channel,
/// 0 where no surface is hit, e.g. above the horizon).
struct RgbdFrame {
    Image rgb;
    Image depth;
};

/// Renders frame `index` (0-based) of the flight. Deterministic for a given FlightParams.
RgbdFrame render_flight_frame(const FlightParams& flight, int index);

}  // namespace deepsea
