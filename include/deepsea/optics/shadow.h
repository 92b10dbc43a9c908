#pragma once
/// \file Lamp shadows from a depth map (docs/snow-shadows.md, "Lamp shadows"): the per-point terms,
/// written once for the runtime's sweep (float) and the tests (double).
///
/// Everything happens in the epipolar plane of a surface point P: the plane through the
/// camera centre O, the lamp L and P. The segment P -> L lies in it, and so do all the camera
/// rays that the segment's image crosses. Seen from the lamp, a point X of that plane has the
/// angle psi between the lamp's position vector a = L / |L| and X - L;
/// shadow_coordinate(X) = -cot(psi) orders the plane's points as the lamp sees them. A surface
/// point Q seen by the camera between P's pixel and the epipole lies on the segment P -> L
/// when its coordinate equals P's, in front of it (nearer the camera) when it is larger.

#include <cmath>

#include "deepsea/optics/vec3t.h"

namespace deepsea {

/// Radius of a lamp's emitting face, metres, where a config gives none: a typical LED lamp
/// head of a work-class ROV or lander (emitting faces of about 5-10 cm across, e.g. the
/// DeepSea Power & Light SeaLite and LED SeaLite families as recalled, not re-read); 4 cm
/// stands for them. It sets the width of the penumbra only.
inline constexpr double kDefaultLampRadius = 0.04;

/// The largest lamp radius a config may give, metres: beyond the size of any lamp head, and
/// the penumbra's small-angle model (R much less than the lamp's distance) fails well before.
inline constexpr double kMaxLampRadius = 0.5;

/// How far behind a surface seen in the depth map the solid is taken to extend along the
/// camera's viewing direction (planar depth), metres, by default: a segment from a point to
/// the lamp that passes behind a seen surface by less than this is blocked. Seafloor rocks,
/// nodules and ripples are solid to well beyond this below their seen face; objects in open
/// water thinner than it cast shadows too long (docs/snow-shadows.md, "Lamp shadows").
inline constexpr double kDefaultShadowThickness = 0.5;

/// -cot(psi) of the point P (camera frame, metres) seen from the lamp at L = |L| a (a the unit
/// vector, lamp_distance = |L| > 0): (|L| - P.a) / |P x a|. Larger is nearer the camera along
/// a viewing ray; equal for the points of one line through the lamp in one epipolar plane.
/// Undefined on the line O-L itself (|P x a| = 0: the epipole's own ray).
template <class T>
inline T shadow_coordinate(Vec3T<T> p, Vec3T<T> a, T lamp_distance) {
    using std::sqrt;
    const Vec3T<T> c = cross(p, a);
    return (lamp_distance - dot(p, a)) / sqrt(dot(c, c));
}

/// The scale that turns a difference of shadow coordinates at P into the penumbra's argument:
/// |P x a|^2 / d1 (metres), d1 = |P - L|. (d/dpsi of -cot(psi) is 1 / sin^2(psi), and
/// sin(psi) = |P x a| / d1.)
template <class T>
inline T shadow_scale(Vec3T<T> p, Vec3T<T> a, T d1) {
    const Vec3T<T> c = cross(p, a);
    return dot(c, c) / d1;
}

/// The penumbra's argument h: how far the lamp's centre stands above the occluder's edge, in
/// units of the lamp's angular radius seen from P. delta = P's shadow coordinate minus the
/// edge's (> 0: the centre is visible), scale = shadow_scale(P), d_o = |P - Q| and s_l =
/// |Q - L| with Q the edge point, radius the lamp's (metres). The lamp's disc seen from P has
/// angular radius R / d1; at the edge, d_o from P and s_l from the lamp, that is the lamp
/// angle R d_o / (d1 s_l), while the edge lies delta sin^2(psi) below the lamp's centre.
template <class T>
inline T penumbra_argument(T delta, T scale, T d_o, T s_l, T radius) {
    return delta * scale * s_l / (radius * d_o);
}

/// The fraction of a disc visible above a straight edge, its centre h radii above the edge:
/// 1 - (acos(h) - h sqrt(1 - h^2)) / pi in [-1, 1], 0 below, 1 above. 1/2 at h = 0.
template <class T>
inline T disc_visible_fraction(T h) {
    using std::acos;
    using std::sqrt;
    if (!(h > T(-1))) return T(0);
    if (!(h < T(1))) return T(1);
    return T(1) - (acos(h) - h * sqrt(T(1) - h * h)) / T(M_PI);
}

}  // namespace deepsea
