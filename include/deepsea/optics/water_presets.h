#pragma once
/// \file Named water presets, "<family>:<type>": jerlov:<IB|II|III|1C|3C|5C> (jerlov.h) and
/// deep:<clear|moderate|nepheloid> (deep_ocean.h). The one place that knows the families, so
/// that the YAML `preset` key, `--water` and bake-library manifests accept the same names.

#include <string>
#include <vector>

#include "deepsea/optics/water.h"

namespace deepsea {

/// Every preset spec, "jerlov:IB", ..., "deep:nepheloid", in the order error messages list them.
const std::vector<std::string>& water_preset_names();

/// True when spec starts with a preset family's prefix ("jerlov:", "deep:"), known type or not:
/// such a spec names a preset, never a file.
bool is_water_preset(const std::string& spec);

/// The preset's water (its name is the spec with '-' for ':', e.g. "deep-clear"). Throws
/// ConfigError naming every known preset for an unknown family or type.
Water water_preset(const std::string& spec);

}  // namespace deepsea
