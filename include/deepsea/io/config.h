#pragma once
/// \file The camera / rig / water YAML configs (docs/config.md): `camera`, `rig` and `water`
/// sections, from one file or several. Unknown keys, missing keys, wrong types and out-of-range
/// values throw ConfigError with "file:line: key: problem". The keys and ranges are those of
/// optics/schema.h, shared with the asset's JSON; the strict reader is src/io/yaml_reader.h.

#include <optional>
#include <string>
#include <vector>

#include "deepsea/camera/model.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/port.h"
#include "deepsea/optics/snow.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// Sections found so far; a later file may add sections but not repeat one.
struct Setup {
    std::optional<Camera> camera;
    /// The camera section's `lens`, `sensor` and `processing` (docs/camera.md): the camera
    /// stage. Unset when the section gives none of them (the ideal camera).
    std::optional<CameraModel> camera_model;
    /// The camera section's `port` (docs/ports.md): the housing's flat or dome port. Unset: no
    /// port (the pinhole looks into the water). Beside the camera, not in CameraModel: the port
    /// changes each pixel's ray, i.e. the renderer's and the baker's geometry (an asset will
    /// record it), while CameraModel is the camera stage applied to rendered radiance.
    std::optional<Port> port;
    std::optional<Rig> rig;
    std::optional<Water> water;
    /// The `snow` section (docs/config.md): marine snow for render. Unset: none (or `off`).
    std::optional<Snow> snow;
};

/// Parses every file in order and merges the sections. Files may hold any subset of
/// `camera`, `rig`, `water`; any other top-level key is an error.
Setup load_setup(const std::vector<std::string>& files);

/// Parses YAML text (file name used only in messages).
Setup parse_setup(const std::string& yaml_text, const std::string& file_name);

/// A water from a spec: a preset ("jerlov:IB", "deep:clear", water_presets.h) or a YAML file
/// with a `water` section.
Water load_water(const std::string& spec);

/// Throws ConfigError naming what is missing unless the setup has camera, rig and water.
void require_complete(const Setup& setup, const std::string& where);

/// Throws ConfigError naming camera.port if the setup has a port: for a command that cannot
/// work through one and would otherwise ignore it (an image without the refraction the user
/// asked for). `what` says what is not built ("surfaces through a port in the reference").
void refuse_port(const Setup& setup, const std::string& where, const std::string& what);

/// The setup as YAML that parse_setup accepts and reads back to the same values (numbers with
/// 17 significant digits, water as explicit values without a preset). Absent sections are
/// left out.
std::string setup_to_yaml(const Setup& setup);

/// Writes `comment` (each line starting with "# ") and setup_to_yaml(setup) to `path`
/// atomically (core's write_atomically).
void write_setup(const std::string& path, const Setup& setup, const std::string& comment = "");

}  // namespace deepsea
