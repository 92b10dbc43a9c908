#pragma once
/// \file The `deepsea:bake` metadata: BakeInfo as JSON and back, and the input hash.
/// Key names and value ranges are those of the YAML configs (optics/schema.h, docs/config.md);
/// docs/asset-format.md lists them.

#include <string>
#include <utility>

#include "deepsea/asset/asset.h"
#include "deepsea/asset/asset_file.h"

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

/// The smallest and largest backscatter at z_max over all columns, per channel: the range the
/// runtime can return.
std::pair<Rgb, Rgb> backscatter_range(const Asset& asset);

/// What `deepsea info --json` prints (one line, no newline) for the file at `path`, with its
/// summary (read_asset_summary) and its loaded values (load_asset): file, bytes, format,
/// value_scale, backscatter_at_z_max {min, max} over all columns, frustum_extent {min, max},
/// preview_voxel_size, grids (with their world bounds), forward_psf (the forward-scatter table:
/// depths, rings, far_depth, paths, seed; null: the small-angle model) and bake. The CLI and the
/// Python module's info() share it.
std::string asset_info_json(const std::string& path, const AssetFileSummary& summary,
                            const Asset& asset);

}  // namespace deepsea
