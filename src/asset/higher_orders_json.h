#pragma once
/// \file The `multiple_scattering` record of an asset's `deepsea:bake` JSON
/// (docs/asset-format.md): the Monte Carlo settings, what they measured, the columns' angular
/// spacing and the check of orders >= 2 (both absent in assets baked before them).

#include <nlohmann/json.hpp>

#include "deepsea/asset/asset.h"

namespace deepsea {

nlohmann::json higher_orders_json(const HigherOrderSettings& h);

/// Inverse of higher_orders_json; AssetError naming the key ("deepsea:bake:
/// multiple_scattering.paths: ...") for a missing, mistyped or out-of-range value.
HigherOrderSettings parse_higher_orders(const nlohmann::json& m);

}  // namespace deepsea
