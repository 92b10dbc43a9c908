#pragma once
/// \file The bake-library manifest (volumes/library.yaml): lists of camera, rig and water files
/// whose every combination is one asset, and optional bake settings. Read with the same strict
/// reader as the configs: errors are ConfigError "file:line: key: problem".

#include <optional>
#include <string>
#include <vector>

namespace deepsea {

/// One asset of a library: its inputs and the file name it is baked to.
struct LibraryEntry {
    std::string camera, rig, water;  ///< files (the water may also be a preset spec, jerlov:IB)
    std::string name;                ///< <camera>__<rig>__<water>.vdb, from the file stems
};

/// The manifest's optional `bake` map, as written: io does not know the baker, so the caller
/// applies these to its settings and validates them (the names are those of `deepsea bake`'s
/// options with underscores).
struct LibraryBakeSettings {
    std::optional<int> xy_step;
    std::optional<int> depth_samples;
    std::optional<std::string> depth_scheme;
    std::optional<std::string> z_max;  ///< metres or "auto"
    std::optional<double> tolerance;
    std::optional<std::string> scattering;  ///< single | multiple
    std::optional<int> paths;               ///< multiple: Monte Carlo paths per column
};

struct LibraryManifest {
    /// Paths relative to the manifest's folder resolved, each list sorted and de-duplicated:
    /// the asset index (and so each shard's share) depends only on the set of inputs, not on
    /// how the manifest happens to list them.
    std::vector<std::string> cameras, rigs, waters;
    LibraryBakeSettings bake;
    /// Every camera x rig x water, cameras outermost.
    std::vector<LibraryEntry> entries;
};

/// Manifest keys (paths relative to the manifest):
///   cameras, rigs, waters   non-empty lists of YAML files (waters also presets: jerlov:IB,
///                           deep:clear, ...); each file must exist
///   bake                    optional map: xy_step, depth_samples, depth_scheme, z_max
///                           (metres or auto), tolerance, scattering (single | multiple),
///                           paths
/// ConfigError for an unknown, missing or mistyped key, a missing file, or two entries that
/// would write the same asset (inputs with one file stem); IoError if the manifest is unreadable.
LibraryManifest load_library_manifest(const std::string& path);

/// As load_library_manifest, from text; relative paths are resolved against `folder`.
LibraryManifest parse_library_manifest(const std::string& yaml_text, const std::string& file_name,
                                       const std::string& folder);

}  // namespace deepsea
