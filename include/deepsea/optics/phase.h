#pragma once
/// \file Normalised phase functions p(psi), 1/sr, with integral over the sphere equal to 1.
/// The volume scattering function is beta(psi) = b * p(psi).

#include <cmath>

namespace deepsea {

/// Henyey-Greenstein p(psi) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos psi)^1.5), 1/sr, for
/// |g| < 1 and cos_psi in [-1, 1]; g = 0 is the isotropic 1 / (4 pi). Templated on the number
/// type for the vectorised float rows (lamp.h's reasons).
template <class T>
inline T henyey_greenstein(T g, T cos_psi) {
    using std::sqrt;
    const T d = T(1) + g * g - T(2) * g * cos_psi;
    return (T(1) - g * g) / (T(4.0 * M_PI) * d * sqrt(d));
}

enum class PhaseKind { Isotropic, HenyeyGreenstein, PetzoldClear, PetzoldCoastal, PetzoldTurbid };

/// A phase function. psi is the scattering angle between the incident propagation direction
/// and the scattered direction (psi = 0: straight on, psi = pi: straight back).
struct Phase {
    PhaseKind kind = PhaseKind::Isotropic;
    double g = 0.0;  ///< Henyey-Greenstein asymmetry, |g| < 1

    /// p(psi) in 1/sr for cos(psi) in [-1, 1].
    double operator()(double cos_psi) const;
    /// Mean cosine <cos psi> = integral of p * cos(psi) over the sphere (g for HG).
    double mean_cosine() const;
    /// Fraction of scattered power within psi <= psi_max (radians).
    double fraction_within(double psi_max) const;
    /// Legendre moment k_l = integral of p * P_l(cos psi) over the sphere for l = 0, 1, 2 (k_0 =
    /// 1, k_1 the mean cosine; Henyey-Greenstein: g^l). By the Funk-Hecke theorem, scattering
    /// multiplies the l-th spherical-harmonic band of the incident radiance by k_l.
    double legendre_moment(int l) const;
};

/// Name as written in configs: "isotropic", "henyey_greenstein", "petzold:clear", ...
const char* to_string(PhaseKind kind);

}  // namespace deepsea
