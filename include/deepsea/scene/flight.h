#pragma once
/// \file Procedural RGB-D seafloor flights: the project's embedded demo input and test source.
/// A camera flies a straight path over the Seafloor of seafloor.h; each frame is ray-traced.
///
/// World frame of the seafloor: x along the flight track, y to the left, z up, metres; the
/// mean seafloor is the plane z = 0. See docs/scene.md.

#include <cstdint>

#include "deepsea/core/frame.h"
#include "deepsea/core/parallel.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"

namespace deepsea {

/// A camera flying a straight path over a procedural seafloor. The defaults are the demo
/// flight: 3 m up, looking straight down, 0.25 m per frame (docs/scene.md).
/// The scene's limits, checked before a frame is rendered: a frame costs about 0.7 s a
/// megapixel on two cores (docs/scene.md), so 16 megapixels (4096 x 4096; a 4K frame is 8.3)
/// keep a frame near ten seconds, and 100000 frames (an hour of 30 Hz video) bound a flight.
inline constexpr long long kMaxFlightPixels = 16ll << 20;
inline constexpr int kMaxFlightSide = 8192;
inline constexpr int kMaxFlightFrames = 100000;
/// The farthest a ray is marched, metres: far beyond what any lamp lights.
inline constexpr double kMaxFlightRange = 1000.0;

struct FlightParams {
    Camera camera;            ///< intrinsics of the rendered frames
    int frames = 8;           ///< frames in the flight (validate_flight checks them all)
    double altitude = 3.0;    ///< metres above the mean seafloor
    double speed = 0.25;      ///< metres travelled per frame (along +x of the seafloor)
    double pitch_deg = 0.0;   ///< 0: looking straight down; > 0 tilts the view forward
    std::uint64_t seed = 1;   ///< same seed, same seafloor, bit for bit
    double relief = 1.0;      ///< height scale of the relief; 0: flat floor, same texture
    double max_range = 50.0;  ///< metres along a ray beyond which nothing is hit (depth 0)
};

/// Renders frame `index` (0-based) of the flight: linear RGB albedo and planar z-depth, 0 where
/// no surface is hit (e.g. above the horizon). Deterministic for a given FlightParams, at any
/// thread count; progress counts image rows. Throws ConfigError for invalid parameters (size,
/// focal lengths, altitude, pitch, relief, index, threads) and for a camera within 5 cm of the
/// seafloor below it.
Frame render_flight_frame(const FlightParams& flight, int index, const Parallel& par = {});

/// Checks every parameter, frames >= 1, and the camera's clearance at all `frames` frames, so
/// that a sequence fails before its first file is written. Throws ConfigError.
void validate_flight(const FlightParams& flight);

/// Camera pose of one frame in the seafloor's world frame: the camera centre and the world
/// directions of the camera axes (OpenCV: x right, y down, z forward).
struct FlightPose {
    Vec3 origin;   ///< camera centre, metres
    Vec3 right;    ///< camera +x
    Vec3 down;     ///< camera +y
    Vec3 forward;  ///< camera +z, the optical axis
};

/// Pose of frame `index`: centre (index * speed, 0, altitude), axis pitched by pitch_deg from
/// straight down toward +x. Image up points along +x (the direction of travel).
FlightPose flight_pose(const FlightParams& flight, int index);

}  // namespace deepsea
