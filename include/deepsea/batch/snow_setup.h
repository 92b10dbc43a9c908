#pragma once
/// \file Marine snow's settings for a render from its parts: the snow (a setup's snow section
/// or a preset), the seed and the lens of the camera model, shared by `render --snow` and the
/// Python Renderer(snow=).

#include <cstdint>
#include <optional>

#include "deepsea/camera/model.h"
#include "deepsea/optics/snow.h"
#include "deepsea/runtime/marine_snow.h"

namespace deepsea {

/// `snow` drawn with `seed` through the lens and sensor of `model` (CameraModel's defaults
/// where there is none: f-number, pixel pitch, focus distance); validated (SchemaError naming
/// the key).
SnowSettings make_snow_settings(const Snow& snow, std::uint64_t seed,
                                const std::optional<CameraModel>& model);

}  // namespace deepsea
