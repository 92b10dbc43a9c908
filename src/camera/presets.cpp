#include "deepsea/camera/presets.h"

#include <cmath>

#include "deepsea/optics/schema.h"

namespace deepsea {

namespace {

/// EMVA 1288 summary figures of a camera's datasheet, and the values deepsea assumes where it
/// is silent. Saturation capacity and temporal dark noise follow from the two figures these
/// datasheets give (docs/camera.md, "Presets"): SNRmax = sqrt(mu_e.sat) and
/// DR = mu_e.sat / sigma_d, both in dB (10 log10 and 20 log10).
struct Figures {
    double pitch_um;         ///< unit cell size
    double snr_max_db;       ///< maximum SNR, dB
    double dr_db;            ///< dynamic range, dB
    int bits;                ///< ADC resolution
    Rgb quantum_efficiency;  ///< assumed: the datasheets give the colour curves as plots only
};

Sensor from_figures(const Figures& f) {
    Sensor s;
    s.pixel_pitch_um = f.pitch_um;
    s.full_well = std::round(std::pow(10.0, f.snr_max_db / 10.0));
    s.dark_noise = std::round(100.0 * s.full_well / std::pow(10.0, f.dr_db / 20.0)) / 100.0;
    s.bits = f.bits;
    s.quantum_efficiency = f.quantum_efficiency;
    // Silent in the datasheets: the gain at which the full well just fills the ADC's range
    // (deepsea's ISO 100, the cameras' 0 dB gain), the default black level and exposure, and
    // deepsea's default dark current, DSNU and PRNU (docs/camera.md, "Presets").
    s.iso = 100.0;
    return s;
}

std::vector<SensorPreset> make_presets() {
    std::vector<SensorPreset> p;
    // MATRIX VISION mvBlueFOX3-2051C: Sony IMX250 (Pregius, 2/3", 3.45 um, global shutter),
    // the pixel of the IMX264, IMX252, IMX253 and IMX255 too. SNRmax 40.3 dB, DNR 71.2 dB.
    p.push_back({"mvbluefox3-2051c", "MATRIX VISION mvBlueFOX3-2051C (Sony IMX250, 3.45 um)",
                 from_figures({3.45, 40.3, 71.2, 12, Rgb{0.45, 0.60, 0.50}})});
    // MATRIX VISION mvBlueFOX3-2024aC: Sony IMX249 (Pregius, 1/1.2", 5.86 um), the pixel of
    // the IMX174. SNRmax 45.1 dB, DNR 73 dB.
    p.push_back({"mvbluefox3-2024ac", "MATRIX VISION mvBlueFOX3-2024aC (Sony IMX249, 5.86 um)",
                 from_figures({5.86, 45.1, 73.0, 12, Rgb{0.55, 0.70, 0.60}})});
    return p;
}

}  // namespace

const std::vector<SensorPreset>& sensor_presets() {
    static const std::vector<SensorPreset> presets = make_presets();
    return presets;
}

std::string sensor_preset_names() {
    std::string names;
    for (const SensorPreset& p : sensor_presets()) names += (names.empty() ? "" : ", ") + p.name;
    return names;
}

const Sensor& sensor_preset(const std::string& name) {
    for (const SensorPreset& p : sensor_presets())
        if (p.name == name) return p.sensor;
    throw SchemaError("camera.sensor.preset",
                      "unknown preset '" + name + "'; known: " + sensor_preset_names());
}

}  // namespace deepsea
