// The camera's normal deviates (noise.h's normal_from_bits, rows of them by normal_row): every
// one of the 2^24 values the 24 bits give, against the normal distribution written out from
// std::erfc in double: the table's error, the Kolmogorov-Smirnov distance, the moments and the
// tails; the vectorised rows against the scalar definition.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "deepsea/camera/noise.h"
#include "rows.h"

namespace deepsea {
namespace {

constexpr double kTwoTo24 = 16777216.0;

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
double normal_pdf(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * M_PI); }

/// The lower half's 2^23 deviates (sign bit clear, t = (2 i + 1) / 2^25 rising), in double.
std::vector<double> lower_half() {
    std::vector<double> z(std::size_t(1) << 23);
    for (std::uint32_t i = 0; i < z.size(); ++i) z[i] = normal_from_bits<double>(i << 8);
    return z;
}

TEST(NormalDeviates, WithinTheTablesErrorOfTheInverseCdf) {
    const std::vector<double> z = lower_half();
    double table = 0.0, tail = 0.0;
    for (std::uint32_t i = 0; i < z.size(); ++i) {
        const double t = (2.0 * i + 1.0) / (2.0 * kTwoTo24);
        // The error in z from the error in the CDF (first order; the second is below 1e-9).
        const double err = (normal_cdf(z[i]) - t) / normal_pdf(z[i]);
        if (t >= 1.0 / 512.0)
            table = std::max(table, std::fabs(err));
        else
            tail = std::max(tail, std::fabs(err) / std::fabs(z[i]));
    }
    EXPECT_LT(table, kNormalTableError);
    EXPECT_GT(table, 0.5 * kNormalTableError);  // the stated error is the table's, not loose
    EXPECT_LT(tail, 1e-6);                      // Giles' erfinv, relative
    // The sign is a bit of its own: the upper half mirrors the lower one exactly.
    for (std::uint32_t i = 0; i < z.size(); i += 4099)
        ASSERT_EQ(normal_from_bits<double>((i << 8) | 0x80000000u), -z[i]) << i;
    EXPECT_NEAR(normal_from_bits<double>(0x80000000u), 5.42, 0.01);  // the tails' ends
    EXPECT_NEAR(normal_from_bits<double>(0u), -5.42, 0.01);
}

TEST(NormalDeviates, KolmogorovDistanceMomentsAndTails) {
    std::vector<double> z = lower_half();
    // Each of the 2^24 values has probability 2^-24; the upper half mirrors the lower, so the
    // largest CDF difference is the lower half's (and at 0, where both halves meet).
    double s2 = 0.0, s4 = 0.0;
    for (double x : z) s2 += x * x, s4 += x * x * x * x;
    const double n = double(z.size());
    const double variance = s2 / n, kurtosis = s4 / n / (variance * variance);
    std::sort(z.begin(), z.end());
    double ks = 0.0;
    for (std::size_t k = 0; k < z.size(); ++k) {
        const double f = normal_cdf(z[k]);
        ks = std::max({ks, std::fabs(f - k / kTwoTo24), std::fabs(f - (k + 1) / kTwoTo24)});
    }
    EXPECT_LT(ks, 2e-5);  // stated: 0.4 x kNormalTableError = 1.5e-5, plus 2^-25
    EXPECT_NEAR(variance, 1.0, 1e-4);
    EXPECT_NEAR(kurtosis, 3.0, 1e-3);
    // Tails: the fraction beyond k sigma, k = 1 .. 5, against 2 Phi(-k) (one side counted).
    for (int k = 1; k <= 5; ++k) {
        const double beyond = double(std::lower_bound(z.begin(), z.end(), -double(k)) - z.begin());
        EXPECT_NEAR(beyond / kTwoTo24, normal_cdf(-k), 2e-5 * normal_pdf(k) + 2.0 / kTwoTo24) << k;
    }
}

TEST(NormalDeviates, RowsAreTheScalarDefinition) {
    // Rows of several lengths (not multiples of 8: the scalar end) and bases, three keys.
    std::vector<float> z(1000);
    std::vector<std::int32_t> index(1000);
    long tails = 0, values = 0;
    for (const std::uint64_t seed : {1ull, 77ull, 123456789ull}) {
        const NoiseKey key = noise_key(seed);
        for (const int n : {1, 7, 8, 384, 999}) {
            for (const std::uint32_t base : {0u, 12345u, 4294966000u}) {
                camera_rows::normal_row(key, base, n, z.data(), index.data());
                for (int i = 0; i < n; ++i) {
                    const std::uint32_t bits = noise_bits(key, base + std::uint32_t(i));
                    const double want = normal_from_bits<double>(bits);
                    // Float rounding of the table's polynomial (fused or not): a few ulps.
                    ASSERT_NEAR(z[i], want, 2e-6 * std::max(1.0, std::fabs(want)))
                        << seed << " " << n << " " << base << " " << i;
                    tails += std::fabs(want) > 2.88;
                    ++values;
                }
            }
        }
    }
    EXPECT_GT(tails, 0);  // the rows' tails (Giles' path) were among the values checked
    EXPECT_LT(double(tails) / values, 0.02);
}

}  // namespace
}  // namespace deepsea
