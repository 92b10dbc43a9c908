#pragma once
/// \file Homogeneous water: beam attenuation c, scattering b, phase function, forward scatter.

#include <string>

#include "deepsea/core/vec.h"
#include "deepsea/optics/phase.h"

namespace deepsea {

/// How forward scatter (docs/model.md) is modelled: the point spread derived from the phase
/// function (`forward_scatter: on`; optics/forward_psf.h), or Jaffe-McGlamery's as in the
/// paper, F = w(d) * (G_sigma(d) * L_s), w(d) = exp(-G d) - exp(-c d), blur sigma in pixels
/// = fx * k * d (`forward_scatter: {G, k}`).
enum class ForwardModel { PhaseFunction, JaffeMcGlamery };

struct ForwardScatter {
    bool enabled = false;
    Rgb G;           ///< 1/m per channel, G <= c
    double k = 0.0;  ///< rad/m, angular spread growth of the forward-scattered light
    ForwardModel model = ForwardModel::JaffeMcGlamery;  ///< G and k are for JaffeMcGlamery
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

/// Jaffe-McGlamery parameters G and k estimated from the water's phase function (a 5 degree
/// cone heuristic, docs/model.md); `forward_scatter: on` now uses the phase-function point
/// spread instead.
ForwardScatter default_forward_scatter(const Water& water);

/// The phase-function point spread (what `forward_scatter: on` means).
inline ForwardScatter phase_function_forward_scatter() {
    ForwardScatter fs;
    fs.enabled = true;
    fs.model = ForwardModel::PhaseFunction;
    return fs;
}

}  // namespace deepsea
