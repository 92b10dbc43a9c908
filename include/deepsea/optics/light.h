#pragma once
/// \file Spotlights and rigs (docs/model.md, "Lamps"): I_l(theta) = I0_l * RID_l(theta).
/// The Gaussian profile itself is lamp.h's gaussian_rid, shared with the runtime.

#include <string>
#include <vector>

#include "deepsea/core/vec.h"
#include "deepsea/optics/shadow.h"

namespace deepsea {

/// Relative radiant intensity distribution of a lamp, a function of the angle theta between
/// the lamp's axis and the emission direction. Value 1 on the axis for the Gaussian.
struct Rid {
    enum class Kind { Gaussian, Table };
    Kind kind = Kind::Gaussian;
    double sigma_deg = 35.0;        ///< Gaussian: exp(-theta^2 / (2 sigma^2)), degrees
    std::vector<double> angle_deg;  ///< Table: ascending angles, degrees, first >= 0
    std::vector<double> value;      ///< Table: relative values >= 0, linear interpolation,
                                    ///< 0 beyond the last angle
    double cutoff_deg = 180.0;      ///< zero for theta > cutoff (degrees)

    /// Relative intensity at angle theta (radians, in [0, pi]).
    double operator()(double theta_rad) const;
};

/// A Rid evaluated on rows of angles, as the runtime's lamp rows need it: out[u] =
/// float(rid(double(theta[u]))), the same bits as Rid::operator() (the same arithmetic, in the
/// same file). A table's interval is found from a quarter-degree bucket of the angle and a
/// step or two, not by a binary search (a call a pixel and lamp was the authors' tabulated
/// lamps' largest cost).
class RidRows {
public:
    explicit RidRows(const Rid& rid);
    void operator()(int n, const float* theta_rad, float* out) const;

private:
    Rid m_rid;
    std::vector<int> m_start;  ///< per bucket q: the angles below q / 4 degrees (none: no buckets)
};

/// One lamp, rigidly mounted with the camera; all quantities in the camera frame.
struct Light {
    std::string name;
    Vec3 position;                 ///< metres
    Vec3 direction{0, 0, 1};       ///< unit vector of the lamp's central axis
    Rgb intensity{1.0, 1.0, 1.0};  ///< radiant intensity on the axis, W/sr, linear R, G, B
    Rid rid;
    /// Radius of the emitting face, metres: the width of the penumbra of its shadows
    /// (optics/shadow.h). Nothing else sees it: the lamp's light is a point's.
    double radius = kDefaultLampRadius;

    /// Radiant intensity I0 * RID(theta) emitted along the unit vector w (W/sr per channel).
    Rgb intensity_toward(const Vec3& w) const;
};

/// The lamps that travel with one camera.
struct Rig {
    std::string name;
    std::vector<Light> lights;
};

}  // namespace deepsea
