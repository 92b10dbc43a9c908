#pragma once
// The `density` preview: the light the rig's lamps put into the water around the rig, on a
// world-space linear grid (docs/asset-format.md, "Preview grid"). Pure arithmetic on optics'
// lamp terms, kept out of asset_write.cpp so that only the file's two translation units
// compile OpenVDB.

#include <cmath>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/asset/asset_file.h"

namespace deepsea::detail {

/// Distance (metres) from a lamp at which the preview's density is 1 on the brightest lamp's
/// axis (nearer: 1, clamped).
inline constexpr double kBeamReference = 0.1;
/// Decades of the source that the density spans: density = 1 + log10(S / S_ref) / kBeamDecades,
/// clamped to [0, 1], so that a beam fades over metres instead of within centimetres (1 / d^2).
inline constexpr double kBeamDecades = 3.0;
/// Density below which a voxel stays background: the beams' visible edge.
inline constexpr double kBeamCut = 0.02;

/// The preview's density of a source s (beam_source) for the reference `scale`.
inline double beam_density(double s, double scale) {
    if (!(s > 0.0)) return 0.0;
    const double d = 1.0 + std::log10(s / scale) / kBeamDecades;
    return d < 0.0 ? 0.0 : (d > 1.0 ? 1.0 : d);
}

/// One preview voxel at world index (a, b, c); world position = voxel_size * (a, b, c) in the
/// file's world frame (camera_to_world).
struct PreviewVoxel {
    int a, b, c;
    float density;  ///< beam_density(scattered power, density_scale)
};

struct Preview {
    double voxel_size = 0.0;           ///< metres
    double density_scale = 0.0;        ///< scattered power per volume (luminance, W/m^3) at 1
    WorldBox domain;                   ///< the world box searched (leaf nodes inside it)
    std::vector<PreviewVoxel> voxels;  ///< in a fixed order (deterministic files)
};

/// Luminance of the light the lamps put into the water at camera-frame point X, per unit
/// volume: sum over lamps of b I0 RID(theta) exp(-c d1) / d1^2 (lamp.h's lamp_term facing the
/// lamp, times the scattering coefficient), Rec. 709 weights.
double beam_source(const Rig& rig, const Water& water, const Vec3& X);

/// The world box of the beams: around each lamp, the distance at which its on-axis density
/// falls to kBeamCut, in front of the camera's plane (world z <= 0), within `extent`.
WorldBox beam_domain(const Rig& rig, const Water& water, const WorldBox& extent);

/// Builds the preview: cubic voxels, at most `max_across` along the domain's longest side,
/// density beam_density(beam_source, density_scale) where it is at least kBeamCut; every voxel's
/// leaf node lies in the domain.
Preview make_preview(const Asset& asset, int max_across);

}  // namespace deepsea::detail
