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
