#pragma once
/// \file One lamp's share of the direct signal at a surface point (docs/model.md, "Lamps" and
/// "Direct signal"), written once for every renderer: the exact reference evaluates these in
/// double, the runtime in float inside `#pragma omp simd` row loops. Hence plain arithmetic
/// on T with unqualified exp/acos/sqrt (GCC maps them to libmvec's vector variants under
/// -ffast-math -fopenmp-simd) and no branches that a select cannot express.

#include <cmath>

#include "deepsea/optics/transmission.h"
#include "deepsea/optics/vec3t.h"

namespace deepsea {

/// Gaussian relative intensity RID(theta) = exp(-theta^2 / (2 sigma^2)): 1 on the lamp's
/// axis, exp(-1/2) at theta = sigma. theta and sigma in radians.
template <class T>
inline T gaussian_rid(T theta, T sigma) {
    using std::exp;
    return exp(-theta * theta / (T(2) * sigma * sigma));
}

/// The angle theta (radians, [0, pi]) whose cosine is cos_theta, clamped to [-1, 1] first:
/// the dot product of two unit vectors can round to just beyond 1. Math: whose acos
/// (core/fast_math.h; the runtime's rows take FastMath's).
template <class Math = ExactMath, class T>
inline T lamp_angle(T cos_theta) {
    const T ct = cos_theta > T(1) ? T(1) : (cos_theta < T(-1) ? T(-1) : cos_theta);
    return Math::acos(ct);
}

/// How a lamp sees a surface point P (lamp.h's inputs, see lamp_geometry).
template <class T>
struct LampGeometry {
    T d1;         ///< lamp to surface, metres
    T cos_n;      ///< n . w, w the unit vector from P to the lamp (Lambert's cosine if > 0)
    T cos_theta;  ///< cosine of theta, the angle between the lamp's axis and lamp -> P
};

/// Geometry of a lamp at L with unit axis `axis` seen from P with unit normal n, given
/// to_light = L - P (camera frame, metres).
template <class T>
inline LampGeometry<T> lamp_geometry(Vec3T<T> to_light, Vec3T<T> n, Vec3T<T> axis) {
    using std::sqrt;
    const T d1 = sqrt(dot(to_light, to_light));
    const T inv = T(1) / d1;
    // theta is measured along lamp -> P = -w
    return {d1, dot(n, to_light) * inv, -dot(axis, to_light) * inv};
}

/// Inverse-square spread and Lambert's cosine, max(0, cos_n) / d1^2 (1/m^2): the lamp's
/// intensity (W/sr) times this is the irradiance (W/m^2) of an unattenuated lamp.
template <class T>
inline T lamp_spread(T d1, T cos_n) {
    return cos_n > T(0) ? cos_n / (d1 * d1) : T(0);
}

/// One channel of one lamp's irradiance at the surface, I0 RID(theta) exp(-c d1) / d1^2
/// max(0, n . w) (W/m^2 for I0 in W/sr, c in 1/m, d1 in metres), from rid = RID(theta) and
/// spread = lamp_spread(d1, cos_n). rid * spread comes first so that the three channels'
/// calls share it.
template <class Math = ExactMath, class T>
inline T lamp_term(T I0, T rid, T spread, T c, T d1) {
    return (rid * spread) * I0 * transmission<Math>(c, d1);
}

/// lamp_term for a Gaussian RID, the RID's exponential and the transmission's taken as one:
/// I0 spread exp(-theta^2 / (2 sigma^2) - c d1) = lamp_term(I0, gaussian_rid(theta, sigma),
/// spread, c, d1). The runtime's rows evaluate this form: one exponential a channel, not two.
template <class Math = ExactMath, class T>
inline T gaussian_lamp_term(T I0, T theta, T sigma, T spread, T c, T d1) {
    return spread * I0 * Math::exp(-theta * theta / (T(2) * sigma * sigma) - c * d1);
}

/// One channel of the radiance J E / pi (W/(m^2 sr)) leaving a Lambertian surface of linear
/// albedo J under irradiance E (the sum of lamp_term over the lamps, W/m^2): the surface as
/// seen through no water, and what forward scatter spreads.
template <class T>
inline T lambertian_radiance(T J, T E) {
    return J * E * T(1.0 / M_PI);
}

/// One channel of the direct signal D = L T from its two factors: the radiance L leaving the
/// surface (lambertian_radiance) and the transmission T of the d2 metres to the camera
/// (transmission(c, d2)). The runtime's rows call this form: they keep L for forward scatter
/// and T as a layer.
template <class T>
inline T direct_signal(T L, T transmitted) {
    return L * transmitted;
}

/// One channel of the direct signal D = (J / pi) E exp(-c d2) (radiance, W/(m^2 sr)): the
/// surface's lambertian_radiance seen over d2 metres of water.
template <class T>
inline T direct_signal(T J, T E, T c, T d2) {
    return direct_signal(lambertian_radiance(J, E), transmission(c, d2));
}

}  // namespace deepsea
