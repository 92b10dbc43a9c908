#pragma once
// Internal to the seafloor: its parameters (docs/scene.md describes the model) and the working
// types that seafloor.cpp (height field and ray marching) and seafloor_albedo.cpp (albedo
// texture) share.

#include <cmath>
#include <cstdint>

#include "deepsea/scene/seafloor.h"
#include "noise.h"

namespace deepsea {

namespace scene_detail {

// Salt slots: every layer of the seafloor draws from its own hash stream.
enum Layer : int {
    kLargeLayer,
    kRippleWarpLayer,
    kRippleMaskLayer,
    kMicroLayer,
    kNoduleLayer,
    kDensityLayer,
    kSandLayer,
    kGrainLayer,
    kSpeckLayer,
    kShellLayer,
    kRippleDirLayer,
    kLayerCount,
};

// Large-scale undulation: fBm, lattice spacing of the first octave in metres.
inline constexpr double kLargeSpacing = 7.0;
inline constexpr double kLargeAmplitude = 0.2;  // m; typical +-0.1 m, bound +-0.26 m
inline constexpr int kLargeOctaves = 3;

// Sand ripples: crest-to-trough height and wavelength (m), crests meandered by a warp noise
// and present only in patches (mask noise), as on current-swept sediment.
inline constexpr double kRippleWavelength = 0.13;
inline constexpr double kRippleHeight = 0.012;
inline constexpr double kRippleWarpSpacing = 1.2;  // m
inline constexpr double kRippleWarpCycles = 1.0;   // crest displacement, in wavelengths
inline constexpr double kRippleMaskSpacing = 2.5;  // m
inline constexpr double kRippleMaskLo = -0.1, kRippleMaskHi = 0.25;

// Micro-relief: mm-scale roughness that gives the depth map's normals some texture.
inline constexpr double kMicroSpacing = 0.04;
inline constexpr double kMicroAmplitude = 0.0015;
inline constexpr int kMicroOctaves = 2;

// Nodules and rocks: at most one per square cell of kCell metres, centre anywhere in the cell,
// semi-major axis at most kMaxRadius; with the lumpy outline, at most kOutline * kMaxRadius
// from its centre.
inline constexpr double kCell = 0.15;
inline constexpr double kMaxRadius = 0.075;
inline constexpr double kDensitySpacing = 3.0;  // m, size of dense and sparse nodule patches
inline constexpr double kRockFraction = 0.04;   // of bumps that are rocks instead of nodules
inline constexpr double kLump = 0.35;           // relative distortion of the outline (lumpiness)
inline constexpr double kLumpFrequency = 1.1;   // lattice cells of lump noise per semi-axis
inline constexpr int kLumpOctaves = 2;
inline constexpr double kNoduleHeightMax = 0.6;  // height / semi-minor axis, nodules
inline constexpr double kHaloReach = 1.5;        // stained sediment out to this many radii
// q^2 = r^2 (1 + kLump lump) lies within r^2 [kLumpLo, kLumpHi].
inline const double kLumpLo = 1.0 - kLump * kNoiseMax * fbm_amplitude(kLumpOctaves);
inline const double kLumpHi = 1.0 + kLump * kNoiseMax * fbm_amplitude(kLumpOctaves);
// A bump of semi-major axis a covers at most the disc of radius a * kOutline.
inline const double kOutline = 1.0 / std::sqrt(kLumpLo);

// gather() collects the bumps within at most kMaxGather metres of a point; a 4 x 4 block of
// cells covers that disc plus the largest halo, so kMaxBumps is never reached.
inline constexpr double kMaxGather = 0.05;
inline constexpr int kMaxBumps = 16;

// Albedo-only layers: bright specks (forams, shell grit) and shell fragments.
inline constexpr double kSpeckCell = 0.03;
inline constexpr double kShellCell = 0.5;

}  // namespace scene_detail

/// What probe() finds at a point besides the height: what the albedo needs, and how far the
/// nearest bump is (for the ray marcher).
struct Seafloor::Probe {
    bool with_height = true;  // false: albedo only (no height terms, bumps out to the halo)
    double height = 0.0;
    double ripple = 0.0;          // ripple(x, y); albedo mode: the caller sets it
    int kind = 0;                 // 0 sand, 1 nodule, 2 rock: the bump that covers the point
    std::uint64_t bump_hash = 0;  // cell hash of that bump
    double bump_q2 = 1.0;         // its normalised radius^2 (0 centre, 1 rim)
    double halo_q2 = 1e9;         // smallest normalised radius^2 of a nodule nearby
    double free = 0.0;            // no bump outline within this distance (m) among those given
};

/// Noise lattice caches for a run of nearby evaluations (one ray, one pixel): the same values
/// as uncached, cheaper.
struct Seafloor::Caches {
    scene_detail::FbmCache<scene_detail::kLargeOctaves> large;
    scene_detail::NoiseCache warp, mask;
    scene_detail::FbmCache<scene_detail::kMicroOctaves> micro;
};

/// One nodule or rock, as gather() finds it.
struct Seafloor::Bump {
    std::uint64_t hash;  // cell hash: the bump's own random stream
    double px, py;       // centre, m
    double a, b;         // semi-axes, m (a >= b)
    double ca, sa;       // direction of the a axis
    double ratio;        // height / b
    double outline;      // radius of the disc that holds the outline (or the halo), m
    bool rock;
};

}  // namespace deepsea
