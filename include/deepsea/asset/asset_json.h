#pragma once
/// \file The `deepsea:bake` metadata: BakeInfo as JSON and back, and the input hash.
/// Key names and value ranges are those of the YAML configs (optics/schema.h, docs/config.md);
/// docs/asset-format.md lists them.

#include <string>

#include "deepsea/asset/asset.h"

namespace deepsea {

/// BakeInfo as a JSON object text. indent < 0: one line (the metadata); >= 0: pretty-printed
/// with that many spaces (`deepsea info --json`). Doubles are written to round-trip exactly.
std::string bake_info_to_json(const BakeInfo& info, int indent = -1);

/// Parses what bake_info_to_json wrote. Throws AssetError ("deepsea:bake: <key>: <problem>")
/// for malformed JSON, a missing key, a value of the wrong type or out of the schema's range.
BakeInfo bake_info_from_json(const std::string& json);

/// Hash of the canonical JSON of the bake's inputs: camera, rig, water and the requested
/// lattice settings (step, scheme, K, z_max or "auto" with its tolerance, quadrature). Not the
/// results (an auto z_max) nor the baker version. "fnv1a64:" and 16 hex digits.
std::string input_hash(const BakeInfo& info);

}  // namespace deepsea
