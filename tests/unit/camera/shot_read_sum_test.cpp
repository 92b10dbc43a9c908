// The Gaussian path below kGaussianShotNoiseFrom electrons: where the read noise is at least
// kGaussianReadNoiseFrom, a Poisson count plus that read noise is drawn as one Cornish-Fisher
// deviate. Its distribution against the exact sum (the Poisson's probabilities convolved with
// the read noise's normal), computed here in double, and the stage's values against it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "camera_test_util.h"
#include "deepsea/camera/noise.h"

namespace deepsea {
namespace {

using namespace camera_test;

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

/// P(N + R <= x) for N ~ Poisson(mu) and R ~ Normal(0, sd^2).
double exact_cdf(double mu, double sd, double x) {
    double p = std::exp(-mu), sum = 0.0;
    for (int k = 0; k < 60 + 12 * mu; ++k) {
        sum += p * normal_cdf((x - k) / sd);
        p *= mu / (k + 1);
    }
    return sum;
}

/// P(X <= x) for the stage's deviate X = mu + s z + b (z^2 - 1), s^2 = mu + sd^2,
/// b = mu / (6 s^2), z standard normal: X <= x where z lies between the quadratic's roots.
double cornish_fisher_cdf(double mu, double sd, double x) {
    const double s = std::sqrt(mu + sd * sd), b = mu / (6.0 * s * s);
    if (b == 0.0) return normal_cdf((x - mu) / s);
    const double c = mu - b - x, disc = s * s - 4.0 * b * c;
    if (disc <= 0.0) return 0.0;
    const double r = std::sqrt(disc);
    return normal_cdf((-s + r) / (2.0 * b)) - normal_cdf((-s - r) / (2.0 * b));
}

/// The largest difference of the two CDFs over x (a fine grid over the whole support).
double kolmogorov_distance(double mu, double sd) {
    const double s = std::sqrt(mu + sd * sd);
    double d = 0.0;
    for (double x = mu - 9.0 * s; x <= mu + 9.0 * s; x += s / 100.0)
        d = std::max(d, std::fabs(exact_cdf(mu, sd, x) - cornish_fisher_cdf(mu, sd, x)));
    return d;
}

TEST(ShotAndReadNoise, OneDeviateIsWithinTheStatedDistanceOfTheExactSum) {
    // From the threshold read noise up (the presets have 2.95 and 7.24 e-), at every mean
    // below kGaussianShotNoiseFrom, where the Poisson path would otherwise be taken.
    for (double sd : {kGaussianReadNoiseFrom, 2.95, 7.24})
        for (double mu : {0.0, 0.05, 0.2, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0})
            EXPECT_LE(kolmogorov_distance(mu, sd), kGaussianSumKs) << "mu " << mu << " sd " << sd;
    // The threshold means something: with half the read noise the sum is far rougher.
    EXPECT_GT(kolmogorov_distance(0.5, 0.5 * kGaussianReadNoiseFrom), 3.0 * kGaussianSumKs);
    EXPECT_EQ(poisson_below(kGaussianReadNoiseFrom), 0.0);
    EXPECT_EQ(poisson_below(0.99 * kGaussianReadNoiseFrom), kGaussianShotNoiseFrom);
}

TEST(ShotAndReadNoise, StageValuesFollowTheExactSumAtLowCounts) {
    // K = 1, 16 bits, no fixed pattern: linear DN - black is the electron count plus read noise.
    CameraModel m = flat_model();
    Sensor& s = m.sensor;
    s.system_gain = 1.0;
    s.dark_current = s.dsnu = s.prnu_percent = 0.0;
    s.dark_noise = 2.5;
    s.full_well = 1e6;
    s.bits = 16;
    s.black_level = 64.0;
    const CameraStage stage(m, pinhole(256, 256, 300.0));
    for (double mu : {0.7, 3.0, 9.0}) {
        Rgb L;
        for (int c = 0; c < 3; ++c) L[c] = mu / stage.electrons_per_radiance(c, s.exposure_time_ms);
        CameraOutput out;
        CameraLayerSet set;
        set.linear_dn = true;
        stage.apply(out, flat(256, 256, L), 21, set);
        std::vector<double> v;
        for (float dn : out.linear_dn.data) v.push_back(dn - 64.0);
        std::sort(v.begin(), v.end());
        const double n = double(v.size());
        double d = 0.0;  // the empirical CDF's largest distance from the exact sum's
        for (std::size_t i = 0; i < v.size(); i += 7) {
            const double f = exact_cdf(mu, 2.5, v[i]);
            d = std::max({d, std::fabs(f - i / n), std::fabs(f - (i + 1) / n)});
        }
        // The approximation's distance plus the sample's: Dvoretzky-Kiefer-Wolfowitz, 1 in 1e6.
        EXPECT_LT(d, kGaussianSumKs + std::sqrt(std::log(2.0 / 1e-6) / (2.0 * n))) << mu;
    }
}

}  // namespace
}  // namespace deepsea
