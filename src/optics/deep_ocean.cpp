#include "deepsea/optics/deep_ocean.h"

#include <iterator>

#include "preset_table.h"

namespace deepsea {

namespace {

// Jerlov's types describe the sunlit surface layer; below it the water is clearer than type I
// and near the seafloor it can be far more turbid. These presets add up, per wavelength,
//
//   c(l) = a_w(l) + b_sw(l) + c_p(l),   b(l) = b_sw(l) + w_p c_p(l),
//   c_p(l) = c_p(660) (l / 660 nm)^-gamma,
//
// and take band means as integrals over B 400-500 nm, G 500-600 nm, R 600-700 nm (1 nm
// steps, trapezoid rule) divided by 100 nm. Sources (docs/water.md has the
// table of every term and how sure each number is):
// - a_w: pure water absorption, R. M. Pope, E. S. Fry, "Absorption spectrum (380-700 nm) of
//   pure water. II. Integrating cavity measurements", Appl. Opt. 36(33), 8710-8723 (1997),
//   2.5 nm table, linearly interpolated. Measured at 22 C; not corrected to deep-sea
//   temperatures or for salt.
// - b_sw: pure seawater scattering, X. Zhang, L. Hu, M.-X. He, "Scattering by pure seawater:
//   effect of salinity", Opt. Express 17(7), 5698-5710 (2009), evaluated at T = 2 C and
//   S = 34.7 (abyssal water), depolarisation ratio 0.039, no pressure term.
// - c_p(660): particle beam attenuation of red (660 nm) transmissometers. Clear deep water:
//   0.01-0.03 1/m (W. D. Gardner, A. V. Mishonov, M. J. Richardson, Deep-Sea Res. II 53 (2006),
//   global transmissometer profiles); benthic nepheloid layers add an excess of up to tenths of
//   1/m near the bottom (Gardner, Richardson, Mishonov, "Global assessment of benthic nepheloid
//   layers and linkage with upper ocean dynamics", Earth Planet. Sci. Lett. 2018). Chosen:
//   0.02 (clear), 0.06 (moderate: a weak nepheloid layer), 0.2 1/m (nepheloid: a strong one).
// - gamma: spectral slope of c_p, 0.5-1 in the ocean, smaller for the larger resuspended
//   particles of a bottom boundary layer (E. Boss et al., J. Geophys. Res. 106(C5), 9509-9516,
//   2001). Chosen: 1.0, 0.8, 0.5.
// - w_p = b_p / c_p: particle single-scattering albedo 0.9 in every band (non-algal and mineral
//   particles scatter far more than they absorb; an assumption good to about +-0.05).
// Dissolved organic matter (CDOM) is left out: it would add absorption in the blue band.
// Phase: the Petzold water whose b at 514 nm (clear 0.036, coastal 0.191, turbid 1.725 1/m) is
// closest to the preset's b(514 nm) (0.025, 0.068, 0.206 1/m) on a log scale, the rule of the
// Jerlov presets. Particles carry 86 % (clear, blue) to over 99 % of the scattering, and
// Petzold's clear and coastal waters are measured mixtures of particles and water of about
// these b.
// clang-format off
constexpr presets::Row kDeep[] = {
    {"clear",     {0.3956, 0.0949, 0.0429}, {0.0192, 0.0235, 0.0309}, PhaseKind::PetzoldClear},
    {"moderate",  {0.4361, 0.1404, 0.0952}, {0.0557, 0.0645, 0.0780}, PhaseKind::PetzoldClear},
    {"nepheloid", {0.5770, 0.2901, 0.2560}, {0.1824, 0.1992, 0.2227}, PhaseKind::PetzoldCoastal},
};
// clang-format on

}  // namespace

const std::vector<std::string>& deep_ocean_types() {
    static const std::vector<std::string> names = presets::types(kDeep, std::size(kDeep));
    return names;
}

Water deep_ocean_water(const std::string& type) {
    return presets::water(kDeep, std::size(kDeep), type, "deep-", "deep-ocean", deep_ocean_types());
}

}  // namespace deepsea
