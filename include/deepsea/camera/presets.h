#pragma once
/// \file Sensors of real cameras, from their published EMVA 1288 figures (docs/camera.md,
/// "Presets": each one's document, the figures taken and what is assumed where it is silent).
/// Selected in YAML as `camera: {sensor: {preset: <name>}}`; the sensor's other keys override
/// the preset's values.

#include <string>
#include <vector>

#include "deepsea/camera/model.h"

namespace deepsea {

/// One camera's sensor as a preset.
struct SensorPreset {
    std::string name;    ///< the YAML value, e.g. "mvbluefox3-2051c"
    std::string camera;  ///< maker, model and sensor, for messages and docs
    Sensor sensor;       ///< every key set: the datasheet's figures and the stated assumptions
};

/// The presets, in the order docs/camera.md lists them.
const std::vector<SensorPreset>& sensor_presets();

/// The names of the presets, comma-separated: "a, b" (for error messages).
std::string sensor_preset_names();

/// The sensor of preset `name`. An unknown name throws SchemaError naming the key
/// `camera.sensor.preset` and the known names, in one line.
const Sensor& sensor_preset(const std::string& name);

}  // namespace deepsea
