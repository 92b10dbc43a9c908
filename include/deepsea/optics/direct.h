#pragma once
/// \file Direct signal of a Lambertian surface lit by the rig (docs/model.md, "Direct signal"):
/// the sums over lamps and channels; the per-pixel terms are lamp.h's, which the runtime's
/// vectorised rows call too.

#include "deepsea/core/vec.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// Radiance reaching the camera from surface point P (camera frame, metres) with unit normal n
/// (facing the camera) and linear albedo J:
/// D = (J / pi) * sum_l I_l(theta_l) exp(-c (d1 + d2)) / d1^2 * max(0, n . w_l).
Rgb direct_radiance(const Rig& rig, const Water& water, const Vec3& P, const Vec3& n, const Rgb& J);

/// The surface's own radiance J/pi E before the path to the camera (direct_radiance without
/// exp(-c d2)): what forward scatter spreads on that path.
Rgb surface_radiance(const Rig& rig, const Water& water, const Vec3& P, const Vec3& n,
                     const Rgb& J);

/// Irradiance-like factor without the albedo and the path back to the camera:
/// sum_l I_l(theta_l) exp(-c d1) / d1^2 * max(0, n . w_l), W/m^2 per channel.
Rgb lamp_irradiance(const Rig& rig, const Water& water, const Vec3& P, const Vec3& n);

}  // namespace deepsea
