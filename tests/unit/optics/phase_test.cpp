#include "deepsea/optics/phase.h"

#include <gtest/gtest.h>

#include <cmath>

namespace deepsea {

namespace {

/// Independent sphere integral: midpoint rule in mu = cos(psi) (1e6 cells), plus extra
/// resolution near mu = 1 through the substitution mu = 1 - s^3 on the last 1 % of mu.
double integrate(const Phase& p, bool times_cos) {
    double sum = 0.0;
    const int n = 1000000;
    for (int i = 0; i < n; ++i) {  // mu in [-1, 0.98]
        const double mu = -1.0 + 1.98 * (i + 0.5) / n;
        sum += p(mu) * (times_cos ? mu : 1.0) * 1.98 / n;
    }
    const double smax = std::cbrt(0.02);
    for (int i = 0; i < n; ++i) {  // mu = 1 - s^3, s in [0, smax]
        const double s = smax * (i + 0.5) / n;
        const double mu = 1.0 - s * s * s;
        sum += p(mu) * (times_cos ? mu : 1.0) * 3.0 * s * s * smax / n;
    }
    return 2.0 * M_PI * sum;
}

}  // namespace

TEST(Phase, EveryKindIntegratesToOne) {
    for (PhaseKind k : {PhaseKind::Isotropic, PhaseKind::HenyeyGreenstein, PhaseKind::PetzoldClear,
                        PhaseKind::PetzoldCoastal, PhaseKind::PetzoldTurbid}) {
        Phase p{k, 0.8};
        EXPECT_NEAR(integrate(p, false), 1.0, 1e-5) << to_string(k);
    }
}

TEST(Phase, HenyeyGreensteinGivesBackG) {
    for (double g : {-0.5, 0.0, 0.3, 0.8, 0.9}) {
        Phase p{PhaseKind::HenyeyGreenstein, g};
        EXPECT_NEAR(integrate(p, true), g, 1e-5) << g;
        EXPECT_NEAR(p.mean_cosine(), g, 1e-5) << g;
    }
}

TEST(Phase, PetzoldKeepsTheShapeOfTheTable) {
    // After normalisation p = beta / b, so ratios between tabulated angles are the table's.
    Phase clear{PhaseKind::PetzoldClear};
    auto at = [&](double deg) { return clear(std::cos(deg * M_PI / 180.0)); };
    EXPECT_NEAR(at(90.0) / at(180.0), 2.459e-4 / 5.019e-4, 1e-3 * 0.49);
    EXPECT_NEAR(at(10.0) / at(30.0), 4.162e-2 / 3.888e-3, 1e-3 * 10.7);
    // b of Petzold clear is 0.036 (Mobley): beta(90) / b is p(90)
    EXPECT_NEAR(at(90.0) * 0.036, 2.459e-4, 0.1 * 2.459e-4);
}

TEST(Phase, PetzoldIsStronglyForward) {
    for (PhaseKind k :
         {PhaseKind::PetzoldClear, PhaseKind::PetzoldCoastal, PhaseKind::PetzoldTurbid}) {
        Phase p{k};
        EXPECT_GT(p.mean_cosine(), 0.85) << to_string(k);
        EXPECT_LT(p.mean_cosine(), 0.97) << to_string(k);
        EXPECT_NEAR(p.mean_cosine(), integrate(p, true), 1e-5) << to_string(k);
        EXPECT_GT(p.fraction_within(10.0 * M_PI / 180.0), 0.5);
        EXPECT_NEAR(p.fraction_within(M_PI), 1.0, 1e-5);
    }
}

}  // namespace deepsea
