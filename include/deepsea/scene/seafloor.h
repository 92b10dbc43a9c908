#pragma once
/// \file The procedural seafloor: height field, albedo texture and ray intersection, the
/// ground that flight.h's demo frames show.
///
/// World frame of the seafloor: x along the flight track, y to the left, z up, metres; the
/// mean seafloor is the plane z = 0. See docs/scene.md.

#include <cstdint>

#include "deepsea/core/vec.h"

namespace deepsea {

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
