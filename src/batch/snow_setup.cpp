#include "deepsea/batch/snow_setup.h"

namespace deepsea {

SnowSettings make_snow_settings(const Snow& snow, std::uint64_t seed,
                                const std::optional<CameraModel>& model) {
    SnowSettings s;
    s.snow = snow;
    s.seed = seed;
    const CameraModel m = model ? *model : CameraModel{};
    s.f_number = m.lens.f_number;
    s.pixel_pitch_um = m.sensor.pixel_pitch_um;
    s.focus_distance_m = m.lens.focus_distance_m;
    s.streaks = snow.streaks;
    // A camera stage exposes for its sensor's time; without one the snow section says.
    s.exposure_time_s = 1e-3 * (model ? model->sensor.exposure_time_ms : snow.exposure_time_ms);
    s.frame_rate_hz = snow.frame_rate_hz;
    validate(s);
    return s;
}

}  // namespace deepsea
