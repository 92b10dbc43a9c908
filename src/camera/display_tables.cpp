#include "display_tables.h"

#include <algorithm>
#include <cstring>

#include "deepsea/camera/sensor.h"
#include "deepsea/core/codes.h"

namespace deepsea::camera_rows {

namespace {

/// The display value of every whole DN in [0, levels) per channel, interleaved (entry 3 dn + c),
/// by the processing kernel itself (chunk by chunk, as a frame's rows).
std::vector<float> display_table(const ProcessParams& pp, const float scale[3], int levels) {
    std::vector<float> lut(3 * std::size_t(levels));
    Scratch t(0, false);
    t.scales(scale);
    const int n = 3 * levels;
    for (int c0 = 0; c0 < n; c0 += kChunk) {
        const int len = std::min(kChunk, n - c0);
        for (int i = 0; i < len; ++i) t.raw[i] = float((c0 + i) / 3);
        process_row(pp, len, t.scale, t.raw, t.tmp, t.image);
        std::memcpy(lut.data() + c0, t.image, sizeof(float) * std::size_t(len));
    }
    return lut;
}

}  // namespace

void processing_params(const CameraModel& model, ProcessParams& pp, float scale[3], Rgb& wb) {
    const Sensor& s = model.sensor;
    const Processing& proc = model.processing;
    pp.black = float(black_level(s));
    wb = proc.white_balance == WhiteBalance::Gains ? proc.gains : Rgb(1.0);
    const double range = max_dn(s) - black_level(s);
    for (int c = 0; c < 3; ++c) scale[c] = float(wb[c] / range);
    if (proc.matrix) {
        pp.matrix = true;
        for (int i = 0; i < 9; ++i) pp.m[i] = float((*proc.matrix)[i]);
    }
    pp.curve = proc.curve;
    pp.inv_gamma = float(1.0 / proc.gamma);
}

bool uses_table(const CameraModel& model) {
    return !model.processing.matrix && model.sensor.bits <= 12 &&
           model.sensor.bayer == BayerPattern::None;
}

DisplayTables::DisplayTables(const ProcessParams& pp, const float scale[3], int levels)
    : lut(display_table(pp, scale, levels)), codes8(lut.size()) {
    quantise8(lut.data(), lut.size(), codes8.data());
}

}  // namespace deepsea::camera_rows
