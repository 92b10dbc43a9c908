#pragma once
// Internal: the camera stage's processing parameters and its tables of every whole DN's
// display value (camera_stage.cpp).

#include <cstdint>
#include <vector>

#include "deepsea/camera/model.h"
#include "rows.h"

namespace deepsea::camera_rows {

/// The processing kernel's parameters of a model, its scales per channel (white-balance gains
/// over the DN range; grey world's gains are a frame's, 1 here) and the gains.
void processing_params(const CameraModel& model, ProcessParams& pp, float scale[3], Rgb& wb);

/// Whether a model's image comes from a table of every whole DN: without a matrix a channel's
/// display value is a function of its raw DN alone, and raw DN are whole numbers (up to 12
/// bits: 48 KB, built from 4096 pixels' processing, a fraction of a frame's).
bool uses_table(const CameraModel& model);

/// Every whole DN in [0, levels)'s display value per channel and its 8-bit code, interleaved
/// (entry 3 dn + c), made by the processing kernel itself (chunk by chunk, as a frame's rows).
struct DisplayTables {
    std::vector<float> lut;            ///< display values
    std::vector<std::uint8_t> codes8;  ///< the same as 8-bit codes (core/codes.h's quantise8)

    DisplayTables(const ProcessParams& pp, const float scale[3], int levels);
};

}  // namespace deepsea::camera_rows
