#include "deepsea/optics/jerlov.h"

#include <iterator>

#include "preset_table.h"

namespace deepsea {

namespace {

// Band means of the measured inherent optical properties of Jerlov water types:
// S. Williamson, J. Hollins, "Measured IOPs of Jerlov water types", Applied Optics (2022),
// doi:10.1364/AO.470464 (data doi:10.6084/m9.figshare.20290782), resampled to 20 wavelengths
// linspace(400, 700, 20) nm. Each band is the plain mean of the samples with
// B: 400 <= lambda < 500 (7 samples), G: 500 <= lambda < 600 (6), R: 600 <= lambda <= 700 (7).
// Phase: the Petzold water whose b at 514 nm (clear 0.036, coastal 0.191, turbid 1.725 1/m)
// is closest to the type's green b on a log scale.
// clang-format off
constexpr presets::Row kJerlov[] = {
    {"IB",  {0.4901, 0.1982, 0.1763}, {0.1140, 0.1223, 0.1357}, PhaseKind::PetzoldCoastal},
    {"II",  {0.5433, 0.2598, 0.2594}, {0.1639, 0.1767, 0.1966}, PhaseKind::PetzoldCoastal},
    {"III", {0.6634, 0.3870, 0.4213}, {0.2704, 0.2872, 0.3106}, PhaseKind::PetzoldCoastal},
    {"1C",  {0.8069, 0.5387, 0.6059}, {0.4050, 0.4272, 0.4570}, PhaseKind::PetzoldCoastal},
    {"3C",  {1.0351, 0.7853, 0.8874}, {0.6117, 0.6448, 0.6883}, PhaseKind::PetzoldTurbid},
    {"5C",  {1.5844, 1.3662, 1.6053}, {1.1330, 1.1938, 1.2740}, PhaseKind::PetzoldTurbid},
};
// clang-format on

}  // namespace

const std::vector<std::string>& jerlov_types() {
    static const std::vector<std::string> names = presets::types(kJerlov, std::size(kJerlov));
    return names;
}

Water jerlov_water(const std::string& type) {
    return presets::water(kJerlov, std::size(kJerlov), type, "jerlov-", "Jerlov", jerlov_types());
}

}  // namespace deepsea
