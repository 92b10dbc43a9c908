#pragma once
/// \file The forward-scatter table of an asset (`deepsea:forward_psf`, docs/asset-format.md):
/// optics' ForwardPsfTable as one line of JSON and back.

#include <string>

#include "deepsea/optics/forward_transport.h"

namespace deepsea {

/// {"depth": [...], "ring_edge": [...], "share": [[r, g, b], ...] (depth-major), "direct":
/// [[r, g, b], ...], "std_error": [[r, g, b], ...], "paths": n, "seed": s}; doubles round-trip.
std::string forward_psf_to_json(const ForwardPsfTable& table);

/// Inverse of forward_psf_to_json, validated (ForwardPsfTable::validate); AssetError
/// "deepsea:forward_psf: <key>: <problem>" for malformed JSON or a bad value.
ForwardPsfTable forward_psf_from_json(const std::string& json);

}  // namespace deepsea
