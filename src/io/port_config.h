#pragma once
// Internal to io: the camera section's `port` key (docs/config.md, docs/ports.md), read into an
// optics Port and written back.

#include <optional>
#include <ostream>

#include "deepsea/optics/camera.h"
#include "deepsea/optics/port.h"
#include "yaml_reader.h"

namespace deepsea {

/// The Port of a `camera` map (`m`, whose keys are checked already) if it has a `port` key
/// (unset: no port, the camera looks into the water as a pinhole). Checks the port's ranges
/// (validate) and its rays over `intrinsics` (check_port_view): a SchemaError, which the
/// caller reports at the key's line.
std::optional<Port> parse_port(const yaml::Document& doc, const yaml::MapView& m,
                               const Camera& intrinsics);

/// The port's keys, indented under `camera:`, every value written (parse_port reads them back
/// to the same port: n_water as one number when the three channels are equal).
void write_port(std::ostream& o, const Port& port);

}  // namespace deepsea
