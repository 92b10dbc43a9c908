#pragma once
// Internal to optics: a table of water presets (jerlov.cpp, deep_ocean.cpp) and the lookups
// both make in theirs.

#include <cstddef>
#include <string>
#include <vector>

#include "deepsea/optics/water.h"

namespace deepsea::presets {

struct Row {
    const char* type;
    Rgb c;  ///< beam attenuation, 1/m, R, G, B band means
    Rgb b;  ///< scattering, 1/m
    PhaseKind phase;
};

/// The table's type names, in its order.
std::vector<std::string> types(const Row* rows, std::size_t n);

/// The water of `type`, named name_prefix + type; a ConfigError naming the family ("Jerlov")
/// and the known types for any other type.
Water water(const Row* rows, std::size_t n, const std::string& type, const char* name_prefix,
            const char* family, const std::vector<std::string>& known);

}  // namespace deepsea::presets
