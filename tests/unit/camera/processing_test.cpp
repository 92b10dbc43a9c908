// Colour processing: white balance (gains, grey world), the camera matrix, the output curves.
#include "deepsea/camera/processing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "camera_test_util.h"
#include "deepsea/camera/sensor.h"
#include "deepsea/colour/srgb.h"

namespace deepsea {
namespace {

using namespace camera_test;

TEST(Processing, FastMathAgainstTheStandardFunctions) {
    // Over the whole range the curves see: pow within a few float roundings of the log.
    double worst_pow = 0.0, worst_log = 0.0;
    for (double x = 1e-8; x <= 1.0; x *= 1.001) {
        const float xf = float(x);
        for (float e : {1.0f / 2.4f, 1.0f / 2.2f, 1.0f / 1.8f, 2.0f}) {
            const double exact = std::pow(double(xf), double(e));
            worst_pow = std::max(worst_pow, std::fabs(fast_pow(xf, e) - exact) / exact);
        }
        worst_log = std::max(worst_log, std::fabs(fast_log2(xf) - std::log2(double(xf))));
    }
    EXPECT_LT(worst_pow, 2e-6);  // 16-bit output resolves 1.5e-5
    EXPECT_LT(worst_log, 3e-6);  // |log2 x| up to 27: a float's rounding there is 2e-6
    EXPECT_EQ(fast_pow(0.0f, 0.5f), 0.0f);
    EXPECT_NEAR(fast_exp2(-3.25f), std::exp2(-3.25), 1e-7);
}

TEST(Processing, SrgbCurve) {
    // The same curve as the colour layer's (the writers' and readers'), to float precision.
    for (float x = 0.0f; x <= 1.0f; x += 1.0f / 4096.0f)
        ASSERT_NEAR(srgb_curve(x), linear_to_srgb(x), 2e-6) << x;
    EXPECT_EQ(srgb_curve(0.0), 0.0);
    EXPECT_NEAR(srgb_curve(1.0), 1.0, 1e-12);
    EXPECT_NEAR(srgb_curve(0.0031308), 0.040450, 1e-6);  // where the two pieces meet
    EXPECT_NEAR(srgb_curve(0.5), 0.735357, 1e-6);
    EXPECT_NEAR(srgb_curve(0.18), 0.461356, 1e-6);  // mid grey
}

/// A stage with no noise and no falloff; DN above black per channel = fraction * range.
struct Bench {
    CameraModel m = flat_model();
    Bench() {
        m.sensor.noise = false;
        m.sensor.dark_current = 0.0;
        m.sensor.bits = 16;
        m.processing.curve = OutputCurve::Linear;
    }
    CameraOutput run(Rgb fraction) const {
        const CameraStage stage(m, pinhole(16, 8, 20.0));
        const double range = max_dn(m.sensor) - black_level(m.sensor);
        Rgb L;
        for (int c = 0; c < 3; ++c)
            L[c] = fraction[c] * range / system_gain(m.sensor) /
                   stage.electrons_per_radiance(c, m.sensor.exposure_time_ms);
        CameraOutput out;
        stage.apply(out, flat(16, 8, L), 0, CameraLayerSet::all());
        return out;
    }
};

constexpr double kQuantum = 1.0 / 64511.0;  // one DN of the 16-bit range above black

TEST(Processing, LinearIsDnOverTheRange) {
    const CameraOutput out = Bench().run({0.1, 0.2, 0.4});
    EXPECT_NEAR(out.image.at(5, 3, 0), 0.1, kQuantum);
    EXPECT_NEAR(out.image.at(5, 3, 1), 0.2, kQuantum);
    EXPECT_NEAR(out.image.at(5, 3, 2), 0.4, kQuantum);
    EXPECT_NEAR(out.noise_free.at(5, 3, 2), 0.4, 1e-5);
}

TEST(Processing, WhiteBalanceGains) {
    Bench b;
    b.m.processing.white_balance = WhiteBalance::Gains;
    b.m.processing.gains = {2.0, 1.0, 0.5};
    const CameraOutput out = b.run({0.1, 0.2, 0.4});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.image.at(0, 0, c), 0.2, 2 * kQuantum) << c;
    b.m.processing.gains = {4.0, 1.0, 1.0};  // 0.4 * 4 clips at 1
    EXPECT_EQ(b.run({0.4, 0.2, 0.4}).image.at(0, 0, 0), 1.0f);
}

TEST(Processing, GreyWorld) {
    Bench b;
    b.m.processing.white_balance = WhiteBalance::GreyWorld;
    const CameraOutput out = b.run({0.05, 0.2, 0.1});
    EXPECT_NEAR(out.white_balance.r, 4.0, 1e-3);
    EXPECT_NEAR(out.white_balance.g, 1.0, 1e-12);
    EXPECT_NEAR(out.white_balance.b, 2.0, 1e-3);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(mean(out.image, c), 0.2, 1e-3) << c;
        EXPECT_NEAR(mean(out.noise_free, c), 0.2, 1e-3) << c;
    }
    // With noise, the grey-world frame is balanced on its own noisy means.
    b.m.sensor.noise = true;
    const CameraOutput noisy = b.run({0.05, 0.2, 0.1});
    EXPECT_NEAR(mean(noisy.image, 0) / mean(noisy.image, 1), 1.0, 1e-3);
}

TEST(Processing, CameraMatrix) {
    Bench b;
    // Swap R and B, mix a tenth of G into R.
    b.m.processing.matrix = std::array<double, 9>{0.0, 0.1, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0};
    const CameraOutput out = b.run({0.1, 0.2, 0.4});
    EXPECT_NEAR(out.image.at(2, 2, 0), 0.42, 2 * kQuantum);
    EXPECT_NEAR(out.image.at(2, 2, 1), 0.2, kQuantum);
    EXPECT_NEAR(out.image.at(2, 2, 2), 0.1, kQuantum);
}

TEST(Processing, OutputCurves) {
    Bench b;
    b.m.processing.curve = OutputCurve::Srgb;
    CameraOutput out = b.run({0.18, 0.5, 1.0});
    EXPECT_NEAR(out.noise_free.at(1, 1, 0), srgb_curve(0.18), 1e-5);
    EXPECT_NEAR(out.noise_free.at(1, 1, 1), srgb_curve(0.5), 1e-5);
    EXPECT_NEAR(out.noise_free.at(1, 1, 2), 1.0, 1e-6);
    b.m.processing.curve = OutputCurve::Gamma;
    b.m.processing.gamma = 2.2;
    out = b.run({0.18, 0.5, 0.0});
    EXPECT_NEAR(out.noise_free.at(1, 1, 0), std::pow(0.18, 1 / 2.2), 1e-5);
    EXPECT_NEAR(out.noise_free.at(1, 1, 1), std::pow(0.5, 1 / 2.2), 1e-5);
    EXPECT_EQ(out.noise_free.at(1, 1, 2), 0.0f);
}

}  // namespace
}  // namespace deepsea
