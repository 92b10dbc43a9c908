#pragma once
/// \file Procedural RGB-D seafloor flights: the project's embedded demo input and test source.
///
/// World frame of the seafloor: x along the flight track, y to the left, z up, metres; the
/// mean seafloor is the plane z = 0. See docs/scene.md.

#include <cstdint>

#include "deepsea/core/image.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"

namespace deepsea {

/// A camera flying a straight path over a procedural seafloor. The defaults are the demo
/// flight: 3 m up, looking straight down, 0.25 m per frame (docs/scene.md).
struct FlightParams {
    Camera camera;            ///< intrinsics of the rendered frames
    int frames = 8;           ///< frames in the flight (validate_flight checks them all)
    double altitude = 3.0;    ///< metres above the mean seafloor
    double speed = 0.25;      ///< metres travelled per frame (along +x of the seafloor)
    double pitch_deg = 0.0;   ///< 0: looking straight down; > 0 tilts the view forward
    std::uint64_t seed = 1;   ///< same seed, same seafloor, bit for bit
    double relief = 1.0;      ///< height scale of the relief; 0: flat floor, same texture
    double max_range = 50.0;  ///< metres along a ray beyond which nothing is hit (depth 0)
    int threads = 0;          ///< worker threads; 0: all cores (output is the same)
};

/// One rendered frame: linear RGB albedo (3 channels) and planar z-depth in metres (1 channel,
/// 0 where no surface is hit, e.g. above the horizon).
struct RgbdFrame {
    Image rgb;
    Image depth;
};

/// Renders frame `index` (0-based) of the flight. Deterministic for a given FlightParams.
/// Throws ConfigError for invalid parameters (size, focal lengths, altitude, pitch, relief,
/// index) and for a camera within 5 cm of the seafloor below it.
RgbdFrame render_flight_frame(const FlightParams& flight, int index);

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

/// What a seafloor point is made of.
enum class SeafloorMaterial {
    Sand,    ///< sediment, ~0.2-0.45 albedo
    Nodule,  ///< manganese nodule, dark brown-black, ~0.05-0.1
    Rock,    ///< small rock or rock fragment, brownish grey
    Shell,   ///< shell fragment or bright speck, ~0.5-0.75
};

/// The seafloor at one horizontal position.
struct SeafloorSample {
    double height = 0.0;  ///< z of the surface, metres
    Rgb albedo;           ///< linear RGB, each in [0, 1]
    SeafloorMaterial material = SeafloorMaterial::Sand;
};

/// The procedural seafloor of one seed: a height field z = h(x, y) (low-frequency undulation,
/// patchy sand ripples, fine micro-relief, nodules and rocks as rounded bumps) and an albedo
/// texture. Pure function of (seed, relief, x, y); cheap to copy.
class Seafloor {
public:
    /// relief scales all heights (0: the plane z = 0); the albedo does not depend on it.
    explicit Seafloor(std::uint64_t seed, double relief = 1.0);

    /// Surface height at (x, y), metres.
    double height(double x, double y) const;
    /// Height, albedo and material at (x, y).
    SeafloorSample sample(double x, double y) const;
    /// Albedo alone at (x, y): what sample() gives, without the cost of the height.
    Rgb albedo(double x, double y) const;
    /// Mean albedo over the n points (x[i], y[i]) of one small footprint, e.g. a pixel's
    /// sub-samples. Colour that varies over centimetres or more is evaluated once, at the
    /// footprint's centroid, which makes this much cheaper than n calls to albedo().
    Rgb mean_albedo(const double* x, const double* y, int n) const;

    /// Bounds of height() over the whole plane, metres.
    double min_height() const { return m_min_height; }
    double max_height() const { return m_max_height; }
    /// Upper bound on |grad h| (a Lipschitz constant), used to step rays safely.
    double max_slope() const { return m_max_slope; }

    /// Intersects the ray o + t d (t >= 0; d need not be unit) with the surface. Returns the
    /// smallest t of a hit with t |d| <= max_range, or a negative value if there is none
    /// (0 if o itself is below the surface).
    double intersect(const Vec3& o, const Vec3& d, double max_range) const;

private:
    struct Probe;
    struct Bump;
    struct Caches;
    int gather(double x, double y, double radius, bool halo, Bump* out) const;
    void probe(double x, double y, const Bump* bumps, int n, Probe& p, Caches& c) const;
    double large_scale(double x, double y, Caches& c) const;
    double ripple(double x, double y, Caches& c) const;
    Rgb sediment_base(double x, double y) const;
    Rgb shade(double x, double y, const Probe& p, const Rgb& base,
              SeafloorMaterial* material) const;

    std::uint64_t m_salt[12] = {};
    double m_relief = 1.0;
    double m_ripple_kx = 1.0, m_ripple_ky = 0.0;  // unit wave direction of the ripples
    double m_min_height = 0.0, m_max_height = 0.0;
    double m_detail_below = 0.0, m_detail_above = 0.0;  // detail range around large_scale()
    double m_max_slope = 0.0, m_large_slope = 0.0;
    double m_base_slope = 0.0;  // slope bound away from bumps
};

}  // namespace deepsea
