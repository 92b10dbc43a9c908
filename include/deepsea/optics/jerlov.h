#pragma once
/// \file Jerlov water-type presets from measured IOPs (Williamson & Hollins 2022).

#include <string>
#include <vector>

#include "deepsea/optics/water.h"

namespace deepsea {

/// The preset names: IB, II, III, 1C, 3C, 5C.
const std::vector<std::string>& jerlov_types();

/// Band-mean c and b (B 400-500 nm, G 500-600 nm, R 600-700 nm) of a Jerlov type with its
/// Petzold phase function. Throws ConfigError for an unknown type.
Water jerlov_water(const std::string& type);

}  // namespace deepsea
