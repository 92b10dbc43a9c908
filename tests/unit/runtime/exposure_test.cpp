#include "deepsea/runtime/exposure.h"

#include <gtest/gtest.h>

#include "deepsea/core/error.h"

namespace deepsea {

TEST(Exposure, ParsesAutoAndFactors) {
    EXPECT_TRUE(parse_exposure("auto").automatic);
    const Exposure e = parse_exposure("2.5");
    EXPECT_FALSE(e.automatic);
    EXPECT_DOUBLE_EQ(e.factor, 2.5);
    EXPECT_THROW(parse_exposure("-1"), ConfigError);
    EXPECT_THROW(parse_exposure("bright"), ConfigError);
    EXPECT_THROW(parse_exposure(""), ConfigError);
}

TEST(Exposure, AutoMapsThePercentileToTheTarget) {
    Image img(100, 10, 3);
    for (int i = 0; i < 1000; ++i) {
        for (int c = 0; c < 3; ++c) img.data[3 * i + c] = float(i) / 1000.0f;  // grey ramp
    }
    Exposure e;
    e.percentile = 0.5;
    e.target = 0.25;
    EXPECT_NEAR(exposure_factor(e, img), 0.25 / 0.4995, 1e-3);
    EXPECT_DOUBLE_EQ(exposure_factor(e, Image(4, 4, 3)), 1.0);  // black: leave it alone
}

}  // namespace deepsea

namespace deepsea {

TEST(Exposure, AutoClipsNoChannelBeyondTheStatedFraction) {
    // Backscatter-like frame: dim in red and green, bright and spread in blue; luminance alone
    // would map its 99.5th percentile to 0.85 and clip most of the blue.
    Image img(200, 50, 3);
    const std::size_t n = std::size_t(img.width) * img.height;
    for (std::size_t i = 0; i < n; ++i) {
        const float t = float(i % 997) / 997.0f;
        img.data[3 * i + 0] = 0.002f * t;
        img.data[3 * i + 1] = 0.01f * t;
        img.data[3 * i + 2] = 0.2f + 0.1f * t;
    }
    const Exposure e;
    const double f = exposure_factor(e, img);
    for (int c = 0; c < 3; ++c) {
        std::size_t clipped = 0;
        for (std::size_t i = 0; i < n; ++i) clipped += img.data[3 * i + c] * f > 1.0;
        EXPECT_LE(double(clipped), e.max_clipped * double(n)) << "channel " << c;
    }
    // It is the blue bound that holds: exposure as bright as that bound allows.
    std::size_t blue_at_top = 0;
    for (std::size_t i = 0; i < n; ++i) blue_at_top += img.data[3 * i + 2] * f > 0.999;
    EXPECT_GT(blue_at_top, 0u);
    Image grey(100, 10, 3);
    for (std::size_t i = 0; i < grey.data.size(); ++i) grey.data[i] = float(i / 3) / 1000.0f;
    EXPECT_NEAR(exposure_factor(e, grey), 0.85 / grey.data[3 * 994], 1e-3);  // luminance rule
}

}  // namespace deepsea

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace deepsea {
namespace {

/// The quantiles as a sort defines them (the implementation before the counting passes): the
/// value of ascending rank count - 1 - floor(fraction count) among the pixels whose luminance
/// is finite.
double sorted_exposure(const Exposure& e, const Image& img) {
    std::vector<float> q[4];
    for (std::size_t i = 0; i + 2 < img.data.size(); i += img.channels) {
        const float r = img.data[i], g = img.data[i + 1], b = img.data[i + 2];
        const float y = 0.2126f * r + 0.7152f * g + 0.0722f * b;
        if (!std::isfinite(y)) continue;
        q[0].push_back(y), q[1].push_back(r), q[2].push_back(g), q[3].push_back(b);
    }
    const auto value = [](std::vector<float> v, double fraction) {
        if (v.empty()) return 0.0;
        const std::size_t over = std::size_t(fraction * double(v.size()));
        std::sort(v.begin(), v.end());
        return double(v[v.size() - 1 - std::min(over, v.size() - 1)]);
    };
    const double p = value(q[0], 1.0 - e.percentile);
    if (!(p > 0.0)) return 1.0;
    double f = e.target / p;
    for (int c = 1; c < 4; ++c) {
        const double v = value(q[c], e.max_clipped);
        if (v > 0.0) f = std::min(f, 1.0 / v);
    }
    return f;
}

}  // namespace

TEST(Exposure, CountingSelectsExactlyTheSortedQuantiles) {
    // Images of every kind of value: spread over many decades, negative, +0 and -0, NaN and
    // inf (left out), and long runs of one value (ties), at sizes down to one pixel. The
    // factor must be the sorted quantiles' to the bit.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (int trial = 0; trial < 60; ++trial) {
        const int w = 1 + int(unit(rng) * 90), h = 1 + int(unit(rng) * 40);
        Image img(w, h, trial % 5 == 0 ? 4 : 3);  // a fourth channel is left out
        const double tie = unit(rng);
        for (float& v : img.data) {
            const double u = unit(rng);
            if (u < 0.02) {
                v = nan;
            } else if (u < 0.03) {
                v = inf;
            } else if (u < 0.06) {
                v = u < 0.045 ? 0.0f : -0.0f;
            } else if (u < 0.1) {
                v = -float(unit(rng));
            } else if (u < 0.1 + 0.5 * tie) {
                v = 0.375f;  // ties
            } else {
                v = float(std::pow(10.0, -6.0 + 8.0 * unit(rng)));
            }
        }
        Exposure e;
        e.percentile = trial % 3 == 0 ? 0.5 : 0.995;
        e.max_clipped = trial % 4 == 0 ? 0.0 : 0.005;
        EXPECT_EQ(exposure_factor(e, img), sorted_exposure(e, img)) << "trial " << trial;
    }
    // more pixels than one thread's share of a counting pass (1 << 14)
    Image big(300, 200, 3);
    for (float& v : big.data) v = float(std::pow(10.0, -3.0 + 4.0 * unit(rng)));
    EXPECT_EQ(exposure_factor(Exposure{}, big), sorted_exposure(Exposure{}, big));
    // every pixel left out: the factor for a black image
    Image bad(3, 2, 3, std::numeric_limits<float>::quiet_NaN());
    EXPECT_EQ(exposure_factor(Exposure{}, bad), 1.0);
}

}  // namespace deepsea
