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
