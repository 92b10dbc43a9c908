#pragma once
/// \file Importance sampling of phase functions, for Monte Carlo transport.

#include <memory>
#include <vector>

#include "deepsea/core/vec.h"
#include "deepsea/optics/phase.h"

namespace deepsea {

/// A scattering direction drawn from a phase function, with its Monte Carlo weight
/// p(cos psi) / pdf(direction): exactly 1 for isotropic and Henyey-Greenstein (sampled by
/// inversion), close to 1 for tabulated phase functions (sampled from a dense table).
struct PhaseSample {
    Vec3 direction;
    double weight = 1.0;
};

/// Samples scattered directions of one phase function. Building it for a tabulated (Petzold)
/// phase function tabulates its CDF once (about 1 ms); sampling is then O(log n).
class PhaseSampler {
public:
    explicit PhaseSampler(const Phase& phase);

    /// cos(psi) for uniform u in [0, 1), and the weight p / pdf.
    double sample_cos(double u, double& weight) const;
    /// Probability density (1/sr) with which sample() returns a direction at cos(psi) from its
    /// axis: p itself for isotropic and Henyey-Greenstein.
    double pdf(double cos_psi) const;
    /// Sampling of the scattering angle psi itself (a 1-D density in psi, not over the sphere)
    /// restricted to [psi_a, psi_b], with density proportional to a dense table of p(cos psi):
    /// next-event estimation along a ray uses it, where psi runs over an interval as the point
    /// moves. angle_mass(a, b) is the table's integral of p over [a, b]; angle_density(psi)
    /// the table's p at psi (piecewise constant), so the sampling density is
    /// angle_density(psi) / angle_mass(a, b).
    double sample_angle(double psi_a, double psi_b, double u) const;
    double angle_mass(double psi_a, double psi_b) const;
    double angle_density(double psi) const;
    /// The phase function sampled.
    const Phase& phase() const { return m_phase; }
    /// A direction at scattering angle psi ~ p from the unit direction `from` (the direction
    /// of travel before scattering), azimuth 2 pi u2.
    PhaseSample sample(const Vec3& from, double u1, double u2) const;

private:
    Phase m_phase;
    std::vector<double> m_psi;   ///< table angles (radians), ascending from 0 to pi
    std::vector<double> m_cdf;   ///< fraction of scattered power within m_psi[i]
    std::vector<double> m_grid;  ///< psi grid for the 1-D angle table, 0 .. pi
    std::vector<double> m_acdf;  ///< integral of p(cos psi) dpsi from 0 to m_grid[i]
    double angle_cdf(double psi) const;
};

/// Unit vector at angle acos(cos_psi) from the unit vector a, azimuth phi (radians) about it.
Vec3 rotate_about(const Vec3& a, double cos_psi, double phi);

}  // namespace deepsea
