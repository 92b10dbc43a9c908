#pragma once
/// \file Deep-ocean water presets: pure seawater plus a particle term from deep-ocean
/// transmissometer data (docs/water.md).

#include <string>
#include <vector>

#include "deepsea/optics/water.h"

namespace deepsea {

/// The preset names: clear, moderate, nepheloid.
const std::vector<std::string>& deep_ocean_types();

/// Band-mean c and b (B 400-500 nm, G 500-600 nm, R 600-700 nm) of a deep-ocean water with its
/// Petzold phase function; name "deep-<type>". Throws ConfigError for an unknown type.
Water deep_ocean_water(const std::string& type);

}  // namespace deepsea
