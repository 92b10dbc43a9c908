#pragma once
/// \file Homogeneous water: beam attenuation c, scattering b, phase function, forward scatter.

#include <string>

#include "deepsea/core/vec.h"
#include "deepsea/optics/phase.h"

namespace deepsea {

/// Jaffe-McGlamery forward scatter (docs/model.md): F = w(d) * (G_sigma(d) * L_s),
/// w(d) = exp(-G d) - exp(-c d), blur sigma in pixels = fx * k * d.
struct ForwardScatter {
    bool enabled = false;
    Rgb G;           ///< 1/m per channel, G <= c
    double k = 0.0;  ///< rad/m, angular spread growth of the forward-scattered light
};

struct Water {
    std::string name;
    Rgb c;  ///< beam attenuation, 1/m, R, G, B
    Rgb b;  ///< scattering coefficient, 1/m, b <= c
    Phase phase;
    ForwardScatter forward;

    /// Volume scattering function beta(psi) = b * p(psi), 1/(m sr), per channel.
    Rgb beta(double cos_psi) const { return b * phase(cos_psi); }
};

/// Forward-scatter parameters derived from the water when the config says `on` without
/// values: see docs/model.md for the derivation.
ForwardScatter default_forward_scatter(const Water& water);

}  // namespace deepsea
