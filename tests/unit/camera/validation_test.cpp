// Out-of-range camera settings are refused with one line that names the key.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "camera_test_util.h"
#include "deepsea/optics/schema.h"

namespace deepsea {
namespace {

using namespace camera_test;

/// The message of the ConfigError that making a stage of the changed model throws ("" if none).
std::string refusal(const std::function<void(CameraModel&)>& change,
                    Camera cam = pinhole(64, 48, 50.0)) {
    CameraModel m;
    change(m);
    try {
        CameraStage stage(m, cam);
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        return e.what();
    }
    return "";
}

TEST(CameraValidation, TheBriefsKeys) {
    EXPECT_EQ(refusal([](CameraModel&) {}), "");
    EXPECT_EQ(refusal([](CameraModel& m) { m.lens.f_number = 0.0; }),
              "camera.lens.f_number: must be > 0, got 0");
    EXPECT_EQ(refusal([](CameraModel& m) { m.lens.f_number = -2.8; }),
              "camera.lens.f_number: must be > 0, got -2.8");
    EXPECT_EQ(refusal([](CameraModel& m) { m.sensor.system_gain = -0.5; }),
              "camera.sensor.system_gain: must be > 0, got -0.5");
    EXPECT_EQ(refusal([](CameraModel& m) { m.sensor.iso = -100.0; }),
              "camera.sensor.iso: must be > 0, got -100");
    EXPECT_EQ(refusal([](CameraModel& m) { m.sensor.full_well = 0.0; }),
              "camera.sensor.full_well: must be >= 1, got 0");
    EXPECT_EQ(refusal([](CameraModel& m) { m.sensor.bits = 7; }),
              "camera.sensor.bits: must be an integer from 8 to 16, got 7");
    EXPECT_EQ(refusal([](CameraModel& m) { m.sensor.bits = 17; }),
              "camera.sensor.bits: must be an integer from 8 to 16, got 17");
    const std::string fold = refusal([](CameraModel& m) { m.lens.distortion.k1 = -0.6; });
    EXPECT_EQ(fold.rfind("camera.lens.distortion: folds the image over", 0), 0u) << fold;
}

TEST(CameraValidation, EveryOtherKey) {
    const auto key_of = [](const std::function<void(CameraModel&)>& change) {
        const std::string m = refusal(change);
        return m.substr(0, m.find(':'));
    };
    const double nan = std::nan("");
    EXPECT_EQ(key_of([&](CameraModel& m) { m.lens.f_number = nan; }), "camera.lens.f_number");
    EXPECT_EQ(key_of([](CameraModel& m) { m.lens.f_number = INFINITY; }), "camera.lens.f_number");
    EXPECT_EQ(key_of([](CameraModel& m) { m.lens.transmittance = 0.0; }),
              "camera.lens.transmittance");
    EXPECT_EQ(key_of([](CameraModel& m) { m.lens.transmittance = 1.5; }),
              "camera.lens.transmittance");
    EXPECT_EQ(key_of([&](CameraModel& m) { m.lens.vignetting.k2 = nan; }),
              "camera.lens.vignetting.k2");
    EXPECT_EQ(key_of([&](CameraModel& m) { m.lens.distortion.p2 = nan; }),
              "camera.lens.distortion.p2");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.pixel_pitch_um = 0.0; }),
              "camera.sensor.pixel_pitch_um");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.exposure_time_ms = 0.0; }),
              "camera.sensor.exposure_time_ms");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.quantum_efficiency.g = 1.2; }),
              "camera.sensor.quantum_efficiency");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.wavelength_nm.b = 45.0; }),
              "camera.sensor.wavelength_nm");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.black_level = 4095.0; }),
              "camera.sensor.black_level");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.dark_noise = -1.0; }),
              "camera.sensor.dark_noise");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.dark_current = -1.0; }),
              "camera.sensor.dark_current");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.dsnu = -1.0; }), "camera.sensor.dsnu");
    EXPECT_EQ(key_of([](CameraModel& m) { m.sensor.prnu_percent = 50.0; }),
              "camera.sensor.prnu_percent");
    EXPECT_EQ(key_of([](CameraModel& m) {
                  m.processing.white_balance = WhiteBalance::Gains;
                  m.processing.gains.r = 0.0;
              }),
              "camera.processing.white_balance.gains");
    EXPECT_EQ(key_of([&](CameraModel& m) {
                  m.processing.matrix = std::array<double, 9>{1, 0, 0, 0, nan, 0, 0, 0, 1};
              }),
              "camera.processing.matrix[4]");
    EXPECT_EQ(key_of([](CameraModel& m) {
                  m.processing.curve = OutputCurve::Gamma;
                  m.processing.gamma = 0.0;
              }),
              "camera.processing.curve.gamma");
    // The intrinsics go through optics' schema.
    EXPECT_EQ(refusal([](CameraModel&) {}, Camera{64, 48, -1.0, 50.0, 31.5, 23.5}).substr(0, 9),
              "camera.fx");
}

}  // namespace
}  // namespace deepsea
