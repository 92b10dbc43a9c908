// The camera's normal deviates as the stage draws them: 2^23 (8.4 million) consecutive values
// of one stream (normal_row over a frame's counters, the hash and the table together), tested as
// a sample of N(0, 1): moments to the 4th order, Kolmogorov-Smirnov and chi-square against the
// normal CDF, the tails beyond 1 to 5 sigma, and no correlation between neighbouring values,
// between streams or between frames. normal_test.cpp checks the table's values themselves
// (every 24-bit input); this checks what the stage's counters and keys make of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "deepsea/camera/noise.h"
#include "rows.h"

namespace deepsea {
namespace {

constexpr int kValues = 1 << 23;

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

/// kValues deviates of a stream from counter 0 on, in the stage's chunks (rows.h, kChunk).
std::vector<float> stream(NoiseKey key) {
    std::vector<float> z(kValues);
    std::vector<std::int32_t> index(camera_rows::kChunk);
    for (int c0 = 0; c0 < kValues; c0 += camera_rows::kChunk)
        camera_rows::normal_row(key, std::uint32_t(c0), std::min(camera_rows::kChunk, kValues - c0),
                                z.data() + c0, index.data());
    return z;
}

/// Pearson correlation of a[i] and b[i + lag].
double correlation(const std::vector<float>& a, const std::vector<float>& b, int lag) {
    double sab = 0.0, sa = 0.0, sb = 0.0, saa = 0.0, sbb = 0.0;
    const std::size_t n = a.size() - std::size_t(lag);
    for (std::size_t i = 0; i < n; ++i) {
        const double x = a[i], y = b[i + std::size_t(lag)];
        sab += x * y, sa += x, sb += y, saa += x * x, sbb += y * y;
    }
    const double m = double(n);
    return (sab / m - sa / m * sb / m) /
           std::sqrt((saa / m - sa / m * sa / m) * (sbb / m - sb / m * sb / m));
}

TEST(NormalStream, MomentsKolmogorovChiSquareAndTails) {
    std::vector<float> z = stream(temporal_key(7, 3, NoiseStream::Shot));
    const double n = kValues;
    double s1 = 0.0, s2 = 0.0, s3 = 0.0, s4 = 0.0;
    for (const float v : z) {
        const double x = v, x2 = x * x;
        s1 += x, s2 += x2, s3 += x2 * x, s4 += x2 * x2;
    }
    // Each against its sampling error (standard errors 1, sqrt(2), sqrt(6), sqrt(24) over
    // sqrt(n)): within 5 of them.
    const double se = 1.0 / std::sqrt(n);
    RecordProperty("mean", std::to_string(s1 / n));
    RecordProperty("variance", std::to_string(s2 / n));
    RecordProperty("third", std::to_string(s3 / n));
    RecordProperty("fourth", std::to_string(s4 / n));
    EXPECT_NEAR(s1 / n, 0.0, 5 * se);
    EXPECT_NEAR(s2 / n, 1.0, 5 * std::sqrt(2.0) * se);
    EXPECT_NEAR(s3 / n, 0.0, 5 * std::sqrt(6.0) * se);   // skewness (mean 0, variance 1)
    EXPECT_NEAR(s4 / n, 3.0, 5 * std::sqrt(96.0) * se);  // 4th moment: variance 96 / n
    // Chi-square over 64 bins of equal probability (by the normal CDF of each deviate): 63
    // degrees of freedom, 103.4 is its 0.1 % point.
    std::vector<double> bins(64, 0.0);
    for (const float v : z) bins[std::min(63, int(normal_cdf(v) * 64.0))] += 1.0;
    double chi2 = 0.0;
    for (const double b : bins) chi2 += (b - n / 64.0) * (b - n / 64.0) / (n / 64.0);
    RecordProperty("chi2", std::to_string(chi2));
    EXPECT_LT(chi2, 103.4);
    // Kolmogorov-Smirnov: sqrt(n) D < 1.95 (the 0.1 % point).
    std::sort(z.begin(), z.end());
    double ks = 0.0;
    for (std::size_t k = 0; k < z.size(); ++k) {
        const double f = normal_cdf(z[k]);
        ks = std::max({ks, std::fabs(f - k / n), std::fabs(f - (k + 1) / n)});
    }
    RecordProperty("ks_sqrt_n", std::to_string(ks * std::sqrt(n)));
    EXPECT_LT(ks * std::sqrt(n), 1.95);
    // Tails, both sides: the count beyond k sigma against n 2 Phi(-k), within 4 Poisson standard
    // deviations (at 5 sigma about 4.8 expected).
    for (int k = 1; k <= 5; ++k) {
        const double lo = double(std::lower_bound(z.begin(), z.end(), float(-k)) - z.begin());
        const double hi = double(z.end() - std::upper_bound(z.begin(), z.end(), float(k)));
        const double want = 2.0 * n * normal_cdf(-k);
        RecordProperty("beyond_" + std::to_string(k),
                       std::to_string(lo + hi) + " of " + std::to_string(want));
        EXPECT_NEAR(lo + hi, want, 4.0 * std::sqrt(want) + 1.0) << k;
    }
    EXPECT_GT(std::max(-z.front(), z.back()), 5.0f);  // the sample reaches beyond 5 sigma
}

TEST(NormalStream, NeighboursStreamsAndFramesAreUncorrelated) {
    const std::vector<float> a = stream(temporal_key(7, 3, NoiseStream::Shot));
    const double bound = 5.0 / std::sqrt(double(kValues));
    // Neighbouring values: the next channel, the next pixel's channel, the next row's (an
    // 800-pixel row is 2400 values).
    for (const int lag : {1, 2, 3, 8, 2400}) EXPECT_LT(std::fabs(correlation(a, a, lag)), bound);
    // Another stream of the frame, the next frame, another camera: value for value.
    for (const NoiseKey other :
         {temporal_key(7, 3, NoiseStream::Read), temporal_key(7, 4, NoiseStream::Shot),
          temporal_key(8, 3, NoiseStream::Shot), fixed_pattern_key(7, NoiseStream::Prnu)})
        EXPECT_LT(std::fabs(correlation(a, stream(other), 0)), bound);
    // Squares too (dependence that a correlation of the values misses).
    std::vector<float> sq(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) sq[i] = a[i] * a[i];
    for (const int lag : {1, 3}) EXPECT_LT(std::fabs(correlation(sq, sq, lag)), bound);
}

}  // namespace
}  // namespace deepsea
