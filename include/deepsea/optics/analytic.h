#pragma once
/// \file Closed forms that the numerical model is checked against.

namespace deepsea {

/// Single-scattering airlight of an isotropic point source of intensity I0 (W/sr) in a
/// homogeneous medium with attenuation c and scattering b and isotropic phase function,
/// seen along a ray of length d_vp, the source at distance d_sv from the viewer and at angle
/// gamma (radians) from the ray. Sun, Ramamoorthi, Narasimhan, Nayar 2005, eq. for L_a,
/// generalised to b != c by the factor b/c.
double sun2005_airlight(double c, double b, double I0, double d_sv, double gamma, double d_vp);

}  // namespace deepsea
