// EMVA 1288's photon transfer method, run on the stage's flat fields as on a real camera: the
// system gain K, the dark noise and the saturation point it recovers are the configured ones.
// And the shot noise's two regimes: Poisson below kGaussianShotNoiseFrom electrons, the
// Gaussian of the same mean and variance above.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "camera_test_util.h"
#include "deepsea/camera/noise.h"
#include "deepsea/camera/sensor.h"

namespace deepsea {
namespace {

using namespace camera_test;

struct Level {
    double mean, variance;  // DN, DN^2 (temporal)
};

/// Mean and temporal variance per channel of the raw DN of two frames of a flat field.
std::array<Level, 3> measure(const CameraStage& stage, Rgb radiance, std::uint64_t key) {
    const Camera& cam = stage.camera();
    const Image field = flat(cam.width, cam.height, radiance);
    CameraOutput a, b;
    CameraLayerSet raw;
    raw.raw = true;
    stage.apply(a, field, key, raw);
    stage.apply(b, field, key + 1, raw);
    std::array<Level, 3> out;
    for (int c = 0; c < 3; ++c)
        out[c] = {(mean(a.raw, c) + mean(b.raw, c)) / 2.0, temporal_variance(a.raw, b.raw, c)};
    return out;
}

TEST(Emva1288, PhotonTransferRecoversGainDarkNoiseAndSaturation) {
    CameraModel m = flat_model();
    Sensor& s = m.sensor;
    s.system_gain = 0.5;
    s.dark_noise = 3.0;
    s.dark_current = 20.0;  // 0.2 e- over 10 ms: part of EMVA's dark noise
    s.full_well = 6000.0;
    s.bits = 12;
    s.black_level = 64.0;
    s.dsnu = 2.0;
    s.prnu_percent = 1.0;
    s.seed = 7;
    const CameraStage stage(m, pinhole(256, 256, 300.0));
    const double K = *s.system_gain;
    // Radiance per channel that gives a fraction f of the full well (photo-electrons).
    const auto radiance = [&](double f) {
        Rgb r;
        for (int c = 0; c < 3; ++c)
            r[c] = f * s.full_well / stage.electrons_per_radiance(c, s.exposure_time_ms);
        return r;
    };
    const std::array<Level, 3> dark = measure(stage, Rgb(0.0), 1000);
    // 12 levels up to 70 % of saturation for K (EMVA's fit range), then 1 % steps across it.
    std::vector<double> fractions = {0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7};
    for (double f = 0.80; f <= 1.2; f += 0.01) fractions.push_back(f);
    std::vector<std::array<Level, 3>> levels;
    for (std::size_t i = 0; i < fractions.size(); ++i)
        levels.push_back(measure(stage, radiance(fractions[i]), 2 * i));
    const double sigma_d_true = std::sqrt(s.dark_noise * s.dark_noise + s.dark_current * 0.01);
    for (int c = 0; c < 3; ++c) {
        // K: slope through the origin of (variance - dark variance) vs (mean - dark mean).
        double sxy = 0.0, sxx = 0.0;
        for (std::size_t i = 0; i < fractions.size(); ++i) {
            if (fractions[i] > 0.7) continue;
            const double x = levels[i][c].mean - dark[c].mean;
            const double y = levels[i][c].variance - dark[c].variance;
            sxy += x * y;
            sxx += x * x;
        }
        const double K_fit = sxy / sxx;
        EXPECT_NEAR(K_fit / K, 1.0, 0.02) << "channel " << c;
        // Dark noise: sigma_d = sqrt(sigma_y.dark^2 - 1/12) / K (quantisation noise removed).
        const double sigma_d = std::sqrt(dark[c].variance - 1.0 / 12.0) / K_fit;
        EXPECT_NEAR(sigma_d / sigma_d_true, 1.0, 0.02) << "channel " << c;
        // Saturation: the level of largest variance (EMVA's mu_y.sat), in electrons. It lies
        // below the full well by about two standard deviations of the pixels' charge (1 % PRNU
        // and 1.3 % shot noise here), where clipping begins to take the variance away.
        std::size_t top = 0;
        for (std::size_t i = 1; i < levels.size(); ++i)
            if (levels[i][c].variance > levels[top][c].variance) top = i;
        const double capacity = (levels[top][c].mean - dark[c].mean) / K_fit;
        EXPECT_GT(capacity, 0.93 * s.full_well) << "channel " << c;
        EXPECT_LE(capacity, 1.0 * s.full_well) << "channel " << c;
        // Beyond it every pixel holds the full well: K full_well + black, the variance falls
        // to the read noise's.
        const Level& last = levels.back()[c];
        EXPECT_NEAR((last.mean - 64.0) / K, s.full_well, 0.002 * s.full_well);
        EXPECT_LT(last.variance, 2.0 * K * K * s.dark_noise * s.dark_noise + 0.2);
    }
}

TEST(Emva1288, ShotNoiseIsPoissonAtLowCounts) {
    // K = 1 and no other noise: DN - black is the electron count itself.
    CameraModel m = flat_model();
    Sensor& s = m.sensor;
    s.system_gain = 1.0;
    s.dark_noise = s.dark_current = s.dsnu = s.prnu_percent = 0.0;
    s.black_level = 16.0;
    const CameraStage stage(m, pinhole(200, 200, 300.0));
    const double mu = 3.0;
    Rgb L;
    for (int c = 0; c < 3; ++c) L[c] = mu / stage.electrons_per_radiance(c, s.exposure_time_ms);
    CameraOutput out;
    stage.apply(out, flat(200, 200, L), 5, CameraLayerSet::all());
    std::vector<double> count(40, 0.0);
    for (float dn : out.raw.data) {
        const double k = dn - 16.0;
        ASSERT_EQ(k, std::floor(k));
        count[std::min<std::size_t>(std::size_t(k), 39)] += 1.0;
    }
    const double n = double(out.raw.data.size());
    double p = std::exp(-mu);
    for (int k = 0; k < 12; ++k) {
        const double expected = n * p, sigma = std::sqrt(n * p * (1.0 - p));
        EXPECT_NEAR(count[k], expected, 4.0 * sigma + 1.0) << "k = " << k;
        p *= mu / (k + 1);
    }
}

TEST(Emva1288, ShotNoiseAboveTheThresholdKeepsThePoissonsThreeMoments) {
    CameraModel m = flat_model();
    Sensor& s = m.sensor;
    s.system_gain = 1.0;
    s.dark_noise = s.dark_current = s.dsnu = s.prnu_percent = 0.0;
    s.full_well = 1e6;
    s.bits = 16;
    s.black_level = 16.0;
    const CameraStage stage(m, pinhole(256, 256, 300.0));
    // Just below the threshold (Poisson), just above it and far above it (Cornish-Fisher):
    // the electrons' (linear DN's) mean, variance and skewness are the Poisson's, mu, mu and
    // 1 / sqrt(mu). A plain Gaussian would have no skewness.
    for (double mu : {kGaussianShotNoiseFrom - 0.5, kGaussianShotNoiseFrom + 0.5, 400.0}) {
        Rgb L;
        for (int c = 0; c < 3; ++c) L[c] = mu / stage.electrons_per_radiance(c, s.exposure_time_ms);
        CameraOutput out;
        stage.apply(out, flat(256, 256, L), 9, CameraLayerSet::all());
        double s1 = 0.0, s2 = 0.0, s3 = 0.0;
        for (float dn : out.linear_dn.data) s1 += dn - 16.0;
        const double n = double(out.linear_dn.data.size()), mean_e = s1 / n;
        for (float dn : out.linear_dn.data) {
            const double d = dn - 16.0 - mean_e;
            s2 += d * d;
            s3 += d * d * d;
        }
        const double variance = s2 / n, skewness = s3 / n / std::pow(variance, 1.5);
        EXPECT_NEAR(mean_e / mu, 1.0, 4.0 / std::sqrt(n * mu)) << mu;
        EXPECT_NEAR(variance / mu, 1.0, 0.02) << mu;
        EXPECT_NEAR(skewness, 1.0 / std::sqrt(mu), 4.0 * std::sqrt(6.0 / n)) << mu;
    }
}

TEST(Emva1288, PoissonByInversionMatchesItsDistribution) {
    EXPECT_EQ(poisson_by_inversion(2.0, 0.1), 0);  // P(0) = 0.135
    EXPECT_EQ(poisson_by_inversion(2.0, 0.2), 1);  // P(<=1) = 0.406
    EXPECT_EQ(poisson_by_inversion(2.0, 0.5), 2);  // P(<=2) = 0.677
    EXPECT_EQ(poisson_by_inversion(0.0, 0.999), 0);
}

}  // namespace
}  // namespace deepsea
