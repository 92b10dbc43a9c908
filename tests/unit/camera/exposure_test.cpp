// Exposure in camera terms: the camera equation, photons at each channel's wavelength,
// electrons, the system gain (or ISO), the black level, the full well and the DN range.
#include <gtest/gtest.h>

#include <cmath>

#include "camera_test_util.h"
#include "deepsea/camera/sensor.h"

namespace deepsea {
namespace {

using namespace camera_test;

TEST(Exposure, ElectronsFromTheCameraEquation) {
    Lens lens;
    lens.f_number = 2.0;
    lens.transmittance = 1.0;
    Sensor s;
    s.pixel_pitch_um = 5.0;
    s.quantum_efficiency = {1.0, 0.5, 0.25};
    s.wavelength_nm = {500.0, 500.0, 500.0};
    // By hand: E = pi * 1 / (4 * 2^2) = 0.19635 W/m^2 for L = 1 W/(m^2 sr); over (5 um)^2 and
    // 1 ms that is 4.9087e-15 J; a 500 nm photon carries h c / lambda = 3.9729e-19 J.
    const double photons = 0.19634954 * 25e-12 * 1e-3 / 3.9728917e-19;
    EXPECT_NEAR(photons, 12355.6, 0.1);
    EXPECT_NEAR(electrons_per_radiance(lens, s, 0, 1.0) / photons, 1.0, 1e-6);
    EXPECT_NEAR(electrons_per_radiance(lens, s, 1, 1.0) / photons, 0.5, 1e-6);
    EXPECT_NEAR(electrons_per_radiance(lens, s, 2, 4.0) / photons, 1.0, 1e-6);  // 4 ms
    // Longer wavelength, more photons per joule; f/4 a quarter of f/2's irradiance; T scales.
    s.wavelength_nm = {650.0, 500.0, 500.0};
    EXPECT_NEAR(electrons_per_radiance(lens, s, 0, 1.0) / photons, 1.3, 1e-6);
    lens.f_number = 4.0;
    lens.transmittance = 0.8;
    EXPECT_NEAR(electrons_per_radiance(lens, s, 1, 1.0) / photons, 0.5 * 0.8 / 4.0, 1e-6);
    EXPECT_NEAR(sensor_irradiance(1.0, 1.0, 2.0), M_PI / 16.0, 1e-15);
    EXPECT_NEAR(photon_energy(500.0), 3.9728917e-19, 1e-25);
}

TEST(Exposure, GainIsoAndBlackLevel) {
    Sensor s;  // 12 bits, full well 10000, ISO 100
    EXPECT_EQ(max_dn(s), 4095.0);
    EXPECT_EQ(black_level(s), 64.0);  // 2^(12 - 6)
    EXPECT_NEAR(system_gain(s), (4095.0 - 64.0) / 10000.0, 1e-15);
    s.iso = 400.0;
    EXPECT_NEAR(system_gain(s), 4.0 * (4095.0 - 64.0) / 10000.0, 1e-15);
    s.system_gain = 0.25;  // K given: ISO ignored
    EXPECT_EQ(system_gain(s), 0.25);
    s.bits = 16;
    s.black_level.reset();
    EXPECT_EQ(black_level(s), 1024.0);
    EXPECT_EQ(max_dn(s), 65535.0);
}

/// Raw DN of a flat field with no noise, axis radiance giving `electrons` in every channel.
Image record(const CameraModel& m, double electrons) {
    const CameraStage stage(m, pinhole(8, 4, 10.0));
    Rgb L;
    for (int c = 0; c < 3; ++c)
        L[c] = electrons / stage.electrons_per_radiance(c, m.sensor.exposure_time_ms);
    CameraOutput out;
    CameraLayerSet set = CameraLayerSet::all();
    stage.apply(out, flat(8, 4, L), 0, set);
    return out.raw;
}

TEST(Exposure, DnFullWellAndClipping) {
    CameraModel m = flat_model();
    m.sensor.noise = false;
    m.sensor.dark_current = 0.0;
    m.sensor.system_gain = 0.3;
    // K e + black, rounded.
    for (float dn : record(m, 1234.0).data) EXPECT_EQ(dn, std::round(0.3 * 1234.0 + 64.0));
    // The full well clips the electrons: K full_well + black.
    for (float dn : record(m, 25000.0).data) EXPECT_EQ(dn, std::round(0.3 * 10000.0 + 64.0));
    // A gain that reaches the DN range before the full well clips at 2^bits - 1.
    m.sensor.system_gain = 1.0;
    for (float dn : record(m, 9000.0).data) EXPECT_EQ(dn, 4095.0);
    m.sensor.bits = 8;
    m.sensor.black_level = 4.0;
    for (float dn : record(m, 100.0).data) EXPECT_EQ(dn, 104.0);
    for (float dn : record(m, 1000.0).data) EXPECT_EQ(dn, 255.0);
    // Dark current adds mu_I t electrons: 500 e-/s over 10 ms is 5 e-.
    m.sensor.dark_current = 500.0;
    for (float dn : record(m, 100.0).data) EXPECT_EQ(dn, 109.0);
}

TEST(Exposure, FrameExposureOverridesTheModel) {
    CameraModel m = flat_model();
    m.sensor.noise = false;
    m.sensor.dark_current = 0.0;
    const CameraStage stage(m, pinhole(8, 4, 10.0));
    const double e10 = stage.electrons_per_radiance(1, 10.0);
    const Image field = flat(8, 4, Rgb(1000.0 / e10));
    CameraOutput out;
    CameraLayerSet set;
    set.raw = true;
    stage.apply(out, field, 0, FrameExposure{20.0, 0.5}, set);  // 2000 e- at K = 0.5
    EXPECT_EQ(out.raw.at(3, 2, 1), 1064.0f);
    EXPECT_EQ(out.exposure.exposure_time_ms, 20.0);
    EXPECT_THROW(stage.apply(out, field, 0, FrameExposure{0.0, 0.5}), ConfigError);
    EXPECT_THROW(stage.apply(out, field, 0, FrameExposure{10.0, -1.0}), ConfigError);
    EXPECT_THROW(stage.apply(out, flat(9, 4, Rgb(1.0)), 0), InputError);
}

}  // namespace
}  // namespace deepsea
