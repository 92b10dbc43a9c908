#pragma once
// Internal to io: the setup's `snow` section (docs/config.md, "snow"), read into an optics Snow
// and written back.

#include <optional>
#include <ostream>

#include "deepsea/optics/snow.h"
#include "yaml_reader.h"

namespace deepsea {

/// The Snow of a `snow` section: a preset's name, `off` (none), or a map of a `preset` and/or
/// the values (`concentration` required without a preset). Checks every value's range
/// (validate(Snow)): a SchemaError naming snow.<key>, which the caller reports at its line.
std::optional<Snow> parse_snow(const yaml::Document& doc, const yaml::Field& f);

/// The section, its preset's name (unless custom) and every value written (parse_snow reads it
/// back to the same snow).
void write_snow(std::ostream& o, const Snow& snow);

}  // namespace deepsea
