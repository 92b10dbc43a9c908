// The sensor presets of real cameras (camera/presets.h, docs/camera.md "Presets"): each one
// makes a valid stage, holds its datasheet's figures, and an unknown name is refused in one
// line that names the key and the known names.
#include "deepsea/camera/presets.h"

#include <gtest/gtest.h>

#include <cmath>

#include "camera_test_util.h"
#include "deepsea/optics/schema.h"

namespace deepsea {
namespace {

using namespace camera_test;

TEST(CameraPresets, EachValidatesAndMakesAStage) {
    ASSERT_GE(sensor_presets().size(), 2u);
    for (const SensorPreset& p : sensor_presets()) {
        CameraModel m;
        m.sensor = p.sensor;
        EXPECT_NO_THROW(validate(m)) << p.name;
        EXPECT_NO_THROW(CameraStage(m, pinhole(64, 48, 50.0))) << p.name;
        EXPECT_EQ(&sensor_preset(p.name), &p.sensor);
        // The full well fills the 12-bit range at the default gain (ISO 100, the cameras' 0 dB).
        EXPECT_EQ(p.sensor.bits, 12) << p.name;
        EXPECT_NEAR(system_gain(p.sensor) * p.sensor.full_well,
                    max_dn(p.sensor) - black_level(p.sensor), 1e-9)
            << p.name;
    }
}

TEST(CameraPresets, FiguresFromTheDatasheets) {
    // EMVA 1288: SNRmax = sqrt(saturation capacity), DR = saturation / dark noise (in dB).
    const auto snr_max_db = [](const Sensor& s) { return 10.0 * std::log10(s.full_well); };
    const auto dr_db = [](const Sensor& s) {
        return 20.0 * std::log10(s.full_well / s.dark_noise);
    };
    const Sensor& imx250 = sensor_preset("mvbluefox3-2051c");
    EXPECT_EQ(imx250.pixel_pitch_um, 3.45);
    EXPECT_NEAR(snr_max_db(imx250), 40.3, 0.005);
    EXPECT_NEAR(dr_db(imx250), 71.2, 0.01);
    const Sensor& imx249 = sensor_preset("mvbluefox3-2024ac");
    EXPECT_EQ(imx249.pixel_pitch_um, 5.86);
    EXPECT_NEAR(snr_max_db(imx249), 45.1, 0.005);
    EXPECT_NEAR(dr_db(imx249), 73.0, 0.01);
}

TEST(CameraPresets, UnknownNameIsRefusedNamingTheKeyAndTheKnownNames) {
    try {
        sensor_preset("blackfly");
        FAIL() << "no error";
    } catch (const SchemaError& e) {
        EXPECT_EQ(
            std::string(e.what()),
            "camera.sensor.preset: unknown preset 'blackfly'; known: " + sensor_preset_names());
        EXPECT_EQ(e.key(), "camera.sensor.preset");
    }
    EXPECT_EQ(sensor_preset_names(), "mvbluefox3-2051c, mvbluefox3-2024ac");
}

}  // namespace
}  // namespace deepsea
