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
    validate(s);
    return s;
}

}  // namespace deepsea
