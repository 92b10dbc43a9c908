// The float exp and acos of the runtime's lamp and direct rows against the standard functions
// in double, over the ranges those rows give them.
#include "deepsea/core/fast_math.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace deepsea {
namespace {

TEST(FastMath, ExpWithinAFewRoundingsOverTheAttenuationsRange) {
    // Exponents of transmission and lamp profiles: -c d - theta^2 / (2 sigma^2) <= 0; below
    // -86.6 the exact value is under 2^-125 and the result about 2^-125.
    double worst = 0.0;
    for (double x = -86.6; x <= 0.0; x += 1.0 / 1024.0 + 1e-7) {
        const float xf = float(x);
        const double exact = std::exp(double(xf));
        worst = std::max(worst, std::fabs(fast_exp(xf) - exact) / exact);
    }
    EXPECT_LT(worst, 1e-6);  // a float's rounding is 6e-8; the rows' tests allow 1e-5
    EXPECT_EQ(fast_exp(0.0f), 1.0f);
    EXPECT_GT(fast_exp(-1000.0f), 0.0f);  // clamped: a tiny number, not garbage
    EXPECT_LT(fast_exp(-1000.0f), 3e-38f);
    EXPECT_NEAR(fast_exp(3.5f), std::exp(3.5), 1e-6 * std::exp(3.5));
    EXPECT_EQ(fast_exp(-2.0), std::exp(-2.0));  // double: the standard function
}

TEST(FastMath, AcosWithinAMicroradianOnMinusOneToOne) {
    double worst = 0.0;
    for (double x = -1.0; x <= 1.0; x += 1.0 / 65536.0) {
        const float xf = float(x);
        worst = std::max(worst, std::fabs(fast_acos(xf) - std::acos(double(xf))));
    }
    EXPECT_LT(worst, 1e-6);
    EXPECT_NEAR(fast_acos(1.0f), 0.0, 1e-7);
    EXPECT_NEAR(fast_acos(-1.0f), M_PI, 1e-6);
    EXPECT_NEAR(fast_acos(0.0f), M_PI / 2, 1e-7);
}

TEST(FastMath, PoliciesGiveTheirFunctions) {
    EXPECT_EQ(ExactMath::exp(-0.7), std::exp(-0.7));
    EXPECT_EQ(ExactMath::acos(0.3), std::acos(0.3));
    EXPECT_EQ(FastMath::exp(-0.7f), fast_exp(-0.7f));
    EXPECT_EQ(FastMath::acos(0.3f), fast_acos(0.3f));
}

}  // namespace
}  // namespace deepsea
