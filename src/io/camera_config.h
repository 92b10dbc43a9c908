#pragma once
// Internal to io: the camera section's camera-stage keys (`lens`, `sensor`, `processing`,
// `auto_exposure`; docs/config.md, docs/camera.md), read into a CameraModel and written back.

#include <optional>
#include <ostream>

#include "deepsea/camera/model.h"
#include "deepsea/optics/camera.h"
#include "yaml_reader.h"

namespace deepsea {

/// The CameraModel of a `camera` map (`m`, whose keys are checked already) if it gives any of
/// lens, sensor, processing and auto_exposure (unset: no camera stage); keys left out keep their
/// defaults. Checks the model (validate) and its distortion over `intrinsics` (check_distortion): a
/// SchemaError, which the caller reports at the key's line.
std::optional<CameraModel> parse_camera_model(const yaml::Document& doc, const yaml::MapView& m,
                                              const Camera& intrinsics);

/// The model's keys, indented under `camera:`, every value written (parse_camera_model reads
/// them back to the same model).
void write_camera_model(std::ostream& o, const CameraModel& model);

}  // namespace deepsea
