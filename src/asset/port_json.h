#pragma once
/// \file The port record of an asset's `deepsea:bake` JSON (docs/asset-format.md, "port"): the
/// camera section's `port` keys (docs/config.md), with n_water always three numbers.

#include <nlohmann/json.hpp>

#include "deepsea/optics/port.h"

namespace deepsea {

/// {"flat": {"normal", "distance", "glass_thickness", "n_air", "n_glass", "n_water"},
/// "fresnel"}, or the same with "dome": {"centre", "radius", ...}.
nlohmann::json port_json(const Port& port);

/// Inverse of port_json, validated (optics' validate(Port)); AssetError naming the key
/// ("deepsea:bake: port.flat.distance: ...") for a missing, mistyped or out-of-range value.
Port parse_port(const nlohmann::json& j);

}  // namespace deepsea
