#pragma once
/// \file Normalised phase functions p(psi), 1/sr, with integral over the sphere equal to 1.
/// The volume scattering function is beta(psi) = b * p(psi).

namespace deepsea {

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
};

/// Name as written in configs: "isotropic", "henyey_greenstein", "petzold:clear", ...
const char* to_string(PhaseKind kind);

}  // namespace deepsea
