// The camera section's camera-stage keys, auto_exposure's too (src/io/camera_config.cpp;
// docs/config.md, docs/camera.md): what they parse to, their defaults, the errors at the key's
// line, and the round trip through setup_to_yaml.
#include <gtest/gtest.h>

#include <string>

#include "../message_of.h"
#include "../replaced.h"
#include "deepsea/camera/presets.h"
#include "deepsea/core/error.h"
#include "deepsea/io/config.h"

namespace deepsea {
namespace {

// Line numbers matter: the error tests below refer to them.
const std::string kCamera =
    "camera:\n"                                                              // 1
    "  width: 800\n"                                                         // 2
    "  height: 600\n"                                                        // 3
    "  fx: 600.0\n"                                                          // 4
    "  fy: 600.0\n"                                                          // 5
    "  cx: 399.5\n"                                                          // 6
    "  cy: 299.5\n"                                                          // 7
    "  lens:\n"                                                              // 8
    "    f_number: 4\n"                                                      // 9
    "    transmittance: 0.8\n"                                               // 10
    "    vignetting: {natural: true, k1: -0.1}\n"                            // 11
    "    distortion: {k1: -0.12, k2: 0.03, p1: 0.001, p2: -0.002, k3: 0}\n"  // 12
    "  sensor:\n"                                                            // 13
    "    pixel_pitch_um: 5.86\n"                                             // 14
    "    exposure_time_ms: 8\n"                                              // 15
    "    quantum_efficiency: [0.4, 0.55, 0.45]\n"                            // 16
    "    system_gain: 0.25\n"                                                // 17
    "    full_well: 32000\n"                                                 // 18
    "    bits: 12\n"                                                         // 19
    "    dark_noise: 6.5\n"                                                  // 20
    "    seed: 7\n"                                                          // 21
    "  processing:\n"                                                        // 22
    "    white_balance: {gains: [1.8, 1.0, 1.4]}\n"                          // 23
    "    matrix: [1.5, -0.3, -0.2, -0.2, 1.4, -0.2, -0.1, -0.4, 1.5]\n"      // 24
    "    curve: {gamma: 2.2}\n";                                             // 25

using test::replaced;

TEST(CameraConfig, KeysParseIntoTheModel) {
    const deepsea::Setup s = parse_setup(kCamera, "cam.yaml");
    ASSERT_TRUE(s.camera && s.camera_model);
    EXPECT_EQ(s.camera->width, 800);
    const CameraModel& m = *s.camera_model;
    EXPECT_EQ(m.lens.f_number, 4.0);
    EXPECT_EQ(m.lens.transmittance, 0.8);
    EXPECT_TRUE(m.lens.vignetting.natural);
    EXPECT_EQ(m.lens.vignetting.k1, -0.1);
    EXPECT_EQ(m.lens.distortion.p2, -0.002);
    EXPECT_EQ(m.sensor.pixel_pitch_um, 5.86);
    EXPECT_EQ(m.sensor.quantum_efficiency.g, 0.55);
    EXPECT_EQ(*m.sensor.system_gain, 0.25);
    EXPECT_EQ(m.sensor.bits, 12);
    EXPECT_EQ(m.sensor.seed, 7u);
    EXPECT_EQ(m.sensor.dsnu, Sensor().dsnu);  // left out: the default
    EXPECT_EQ(m.sensor.bayer, BayerPattern::None);
    EXPECT_EQ(m.processing.white_balance, WhiteBalance::Gains);
    EXPECT_EQ(m.processing.gains.b, 1.4);
    ASSERT_TRUE(m.processing.matrix);
    EXPECT_EQ((*m.processing.matrix)[7], -0.4);
    EXPECT_EQ(m.processing.curve, OutputCurve::Gamma);
    EXPECT_EQ(m.processing.gamma, 2.2);
    // No lens, sensor or processing: no camera stage.
    const deepsea::Setup pinhole =
        parse_setup(kCamera.substr(0, kCamera.find("  lens:")), "cam.yaml");
    EXPECT_TRUE(pinhole.camera && !pinhole.camera_model);
    // Words for the white balance and the curve.
    const deepsea::Setup words =
        parse_setup(replaced(replaced(kCamera, "{gains: [1.8, 1.0, 1.4]}", "grey_world"),
                             "{gamma: 2.2}", "srgb"),
                    "cam.yaml");
    EXPECT_EQ(words.camera_model->processing.white_balance, WhiteBalance::GreyWorld);
    EXPECT_EQ(words.camera_model->processing.curve, OutputCurve::Srgb);
    // Each Bayer pattern by its name.
    for (const auto& [name, p] :
         {std::pair{"rggb", BayerPattern::Rggb}, std::pair{"bggr", BayerPattern::Bggr},
          std::pair{"grbg", BayerPattern::Grbg}, std::pair{"gbrg", BayerPattern::Gbrg},
          std::pair{"none", BayerPattern::None}})
        EXPECT_EQ(parse_setup(replaced(kCamera, "    seed: 7", std::string("    bayer: ") + name),
                              "cam.yaml")
                      .camera_model->sensor.bayer,
                  p)
            << name;
}

std::string error_of(const std::string& text) {
    return test::message_of<ConfigError>([&] { parse_setup(text, "cam.yaml"); });
}

TEST(CameraConfig, BadValuesNameFileLineAndKey) {
    struct Bad {
        std::string from, to, expect;
    };
    const Bad cases[] = {
        {"    f_number: 4", "    f_number: 0",
         "cam.yaml:9: camera.lens.f_number: must be > 0, got 0"},
        {"    system_gain: 0.25", "    system_gain: -1",
         "cam.yaml:17: camera.sensor.system_gain: must be > 0, got -1"},
        {"    full_well: 32000", "    full_well: 0",
         "cam.yaml:18: camera.sensor.full_well: must be >= 1, got 0"},
        {"    bits: 12", "    bits: 17",
         "cam.yaml:19: camera.sensor.bits: must be an integer from 8 to 16, got 17"},
        {"    bits: 12", "    bits: 12.5", "cam.yaml:19: camera.sensor.bits: expected an integer"},
        {"    f_number: 4", "    f_numbr: 4", "cam.yaml:9: camera.lens.f_numbr:"},
        {"    system_gain: 0.25", "    system_gain: 0.25\n    iso: 200",
         "cam.yaml:18: camera.sensor.iso: give system_gain or iso, not both"},
        {"{k1: -0.12, k2: 0.03", "{k1: -0.9, k2: 0.03",
         "cam.yaml:12: camera.lens.distortion: folds the image over"},
        {"{gamma: 2.2}", "cubic", "cam.yaml:25: camera.processing.curve: expected linear"},
        {"[1.8, 1.0, 1.4]", "[1.8, 0, 1.4]",
         "cam.yaml:23: camera.processing.white_balance.gains: must be in (0, 1000]"},
        {"-0.1, -0.4, 1.5]", "-0.1, -0.4]", "cam.yaml:24: camera.processing.matrix:"},
        {"  lens:", "  lenses:", "cam.yaml:8: camera.lenses:"},
        {"    seed: 7", "    bayer: rgbg",
         "cam.yaml:21: camera.sensor.bayer: unknown Bayer pattern 'rgbg'; known: none, rggb, "
         "bggr, grbg, gbrg"},
    };
    for (const Bad& c : cases) {
        const std::string e = error_of(replaced(kCamera, c.from, c.to));
        EXPECT_EQ(e.rfind(c.expect, 0), 0u) << "got: " << e << "\nexpected: " << c.expect;
    }
}

TEST(CameraConfig, SensorPresetWithOverrides) {
    // The preset's values, and the keys given beside it override them (whatever their order).
    const std::string head = kCamera.substr(0, kCamera.find("  sensor:"));
    const deepsea::Setup s = parse_setup(head +
                                             "  sensor:\n"
                                             "    exposure_time_ms: 4\n"
                                             "    dark_noise: 5\n"
                                             "    preset: mvbluefox3-2051c\n",
                                         "cam.yaml");
    ASSERT_TRUE(s.camera_model);
    const Sensor& got = s.camera_model->sensor;
    const Sensor& preset = sensor_preset("mvbluefox3-2051c");
    EXPECT_EQ(got.full_well, preset.full_well);
    EXPECT_EQ(got.pixel_pitch_um, 3.45);
    EXPECT_EQ(got.quantum_efficiency.g, preset.quantum_efficiency.g);
    EXPECT_EQ(got.dark_noise, 5.0);
    EXPECT_EQ(got.exposure_time_ms, 4.0);
    // An unknown name: one line at its line, naming the key and the known names.
    const std::string e = error_of(head + "  sensor:\n    preset: gopro\n");
    EXPECT_EQ(e, "cam.yaml:14: camera.sensor.preset: unknown preset 'gopro'; known: " +
                     sensor_preset_names());
}

// The pinhole keys and an auto_exposure map alone (lines 8-14).
const std::string kAutoExposure = kCamera.substr(0, kCamera.find("  lens:")) +
                                  "  auto_exposure:\n"                // 8
                                  "    metering: {percentile: 98}\n"  // 9
                                  "    target: 0.4\n"                 // 10
                                  "    damping: 0.25\n"               // 11
                                  "    min_exposure_time_ms: 0.05\n"  // 12
                                  "    max_exposure_time_ms: 33\n"    // 13
                                  "    max_system_gain: 4\n";         // 14

TEST(CameraConfig, AutoExposureKeys) {
    const deepsea::Setup s = parse_setup(kAutoExposure, "cam.yaml");
    ASSERT_TRUE(s.camera_model);  // the map alone makes a camera stage (default lens, sensor)
    const AutoExposure& a = s.camera_model->auto_exposure;
    EXPECT_TRUE(a.enabled);  // on when the map is given
    EXPECT_EQ(a.metering, Metering::Percentile);
    EXPECT_EQ(a.percentile, 98.0);
    EXPECT_EQ(a.target, 0.4);
    EXPECT_EQ(a.damping, 0.25);
    EXPECT_EQ(a.min_exposure_time_ms, 0.05);
    EXPECT_EQ(a.max_exposure_time_ms, 33.0);
    EXPECT_FALSE(a.min_system_gain);  // left out: the sensor's K
    EXPECT_EQ(*a.max_system_gain, 4.0);
    const deepsea::Setup off =
        parse_setup(replaced(replaced(kAutoExposure, "{percentile: 98}", "mean"),
                             "    target: 0.4\n", "    enabled: false\n"),
                    "cam.yaml");
    EXPECT_FALSE(off.camera_model->auto_exposure.enabled);
    EXPECT_EQ(off.camera_model->auto_exposure.metering, Metering::Mean);
    EXPECT_EQ(off.camera_model->auto_exposure.target, AutoExposure().target);
    // Without the map: off, the defaults.
    EXPECT_FALSE(parse_setup(kCamera, "cam.yaml").camera_model->auto_exposure.enabled);
}

TEST(CameraConfig, AutoExposureBadValuesNameFileLineAndKey) {
    struct Bad {
        std::string from, to, expect;
    };
    const Bad cases[] = {
        {"damping: 0.25", "damping: 0",
         "cam.yaml:11: camera.auto_exposure.damping: must be in (0, 1], got 0"},
        {"target: 0.4", "target: 1.2",
         "cam.yaml:10: camera.auto_exposure.target: must be in (0, 1), got 1.2"},
        {"{percentile: 98}", "{percentile: 0}",
         "cam.yaml:9: camera.auto_exposure.metering.percentile: must be in (0, 100], got 0"},
        {"{percentile: 98}", "median",
         "cam.yaml:9: camera.auto_exposure.metering: expected mean or {percentile: p}, got "
         "'median'"},
        {"{percentile: 98}", "{median: 50}", "cam.yaml:9: camera.auto_exposure.metering.median:"},
        {"max_exposure_time_ms: 33", "max_exposure_time_ms: 0.01",
         "cam.yaml:13: camera.auto_exposure.max_exposure_time_ms: must be >= "
         "min_exposure_time_ms = 0.05 ms, got 0.01"},
        {"max_system_gain: 4", "max_system_gain: 0.1",
         "cam.yaml:14: camera.auto_exposure.max_system_gain: must be >= min_system_gain"},
        {"    damping: 0.25", "    dampng: 0.25", "cam.yaml:11: camera.auto_exposure.dampng:"},
        {"target: 0.4", "target: \"0.4\"",
         "cam.yaml:10: camera.auto_exposure.target: expected a number"},
    };
    for (const Bad& c : cases) {
        const std::string e = error_of(replaced(kAutoExposure, c.from, c.to));
        EXPECT_EQ(e.rfind(c.expect, 0), 0u) << "got: " << e << "\nexpected: " << c.expect;
    }
}

TEST(CameraConfig, SetupToYamlRoundTrips) {
    const deepsea::Setup s = parse_setup(kCamera, "cam.yaml");
    const deepsea::Setup t = parse_setup(setup_to_yaml(s), "round.yaml");
    ASSERT_TRUE(t.camera_model);
    const CameraModel &a = *s.camera_model, &b = *t.camera_model;
    EXPECT_EQ(a.lens.distortion.k2, b.lens.distortion.k2);
    EXPECT_EQ(a.lens.vignetting.k1, b.lens.vignetting.k1);
    EXPECT_EQ(a.sensor.wavelength_nm.r, b.sensor.wavelength_nm.r);
    EXPECT_EQ(*a.sensor.system_gain, *b.sensor.system_gain);
    EXPECT_EQ(a.sensor.black_level.has_value(), b.sensor.black_level.has_value());
    EXPECT_EQ(a.sensor.seed, b.sensor.seed);
    EXPECT_EQ(a.processing.gains.r, b.processing.gains.r);
    EXPECT_EQ(*a.processing.matrix, *b.processing.matrix);
    EXPECT_EQ(a.processing.gamma, b.processing.gamma);
    EXPECT_EQ(a.auto_exposure.enabled, b.auto_exposure.enabled);  // off, written as off
    // A Bayer pattern, written back by its name.
    deepsea::Setup m = s;
    m.camera_model->sensor.bayer = BayerPattern::Grbg;
    EXPECT_EQ(parse_setup(setup_to_yaml(m), "round.yaml").camera_model->sensor.bayer,
              BayerPattern::Grbg);
    // The auto exposure's keys, on.
    const deepsea::Setup u = parse_setup(kAutoExposure, "cam.yaml");
    const AutoExposure& ua = u.camera_model->auto_exposure;
    const deepsea::Setup v = parse_setup(setup_to_yaml(u), "round.yaml");
    const AutoExposure& va = v.camera_model->auto_exposure;
    EXPECT_TRUE(va.enabled);
    EXPECT_EQ(ua.percentile, va.percentile);
    EXPECT_EQ(ua.target, va.target);
    EXPECT_EQ(ua.damping, va.damping);
    EXPECT_EQ(ua.min_exposure_time_ms, va.min_exposure_time_ms);
    EXPECT_EQ(ua.max_exposure_time_ms, va.max_exposure_time_ms);
    EXPECT_EQ(ua.min_system_gain.has_value(), va.min_system_gain.has_value());
    EXPECT_EQ(*ua.max_system_gain, *va.max_system_gain);
    // A camera section without the stage writes none.
    deepsea::Setup plain = s;
    plain.camera_model.reset();
    EXPECT_EQ(setup_to_yaml(plain).find("lens:"), std::string::npos);
}

}  // namespace
}  // namespace deepsea
