// The sweep's quick penumbra test (lamp_shadows_lines.h, penumbra_past) against the penumbra's
// argument it stands for (penumbra_lane): where it says the whole disc is seen past an edge, the
// argument is at least 1 with a margin far above float rounding and the vector square root's
// and reciprocal's error, so the quick test never changes a pixel (docs/snow-shadows.md,
// "Sweep"); and it says so wherever the argument is clearly above 1, so it saves the work.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "deepsea/core/random.h"
#include "lamp_shadows_lines.h"

using namespace deepsea;

namespace {

/// The argument h of penumbra_lane in double (no clamp below 1e-30: the cases have d2 > 1e-12).
double exact_h(float gp, float k, float px, float py, float pz, float eg, float ex, float ey,
               float ez, float es, float R) {
    const double dx = double(px) - ex, dy = double(py) - ey, dz = double(pz) - ez;
    return (double(gp) - eg) * k * es / (R * std::sqrt(dx * dx + dy * dy + dz * dz));
}

}  // namespace

TEST(PenumbraPast, NeverWhereTheDiscIsNotWhollySeenAndAlwaysWhereClearly) {
    Rng rng(mix_seed(26, 6));
    const float radii[] = {1e-5f, 0.005f, 0.04f, 0.2f, 3.0f};
    long past = 0, clear = 0, clear_past = 0, near = 0;
    double least_past = 1e30;
    for (int n = 0; n < 2000000; ++n) {
        const float R = radii[n % 5];
        // a point P and an edge E on surfaces 0.2-20 m away, 1e-5 to 1 m apart
        const float pz = float(0.2 + 19.8 * rng.uniform());
        const float px = float((rng.uniform() - 0.5) * pz), py = float((rng.uniform() - 0.5) * pz);
        const double sep = std::pow(10.0, -5.0 + 5.0 * rng.uniform());
        const float ex = float(px + sep * (rng.uniform() - 0.5));
        const float ey = float(py + sep * (rng.uniform() - 0.5));
        const float ez = float(pz + sep * (rng.uniform() - 0.5));
        const float k = float(0.01 + 10.0 * rng.uniform()), es = float(0.2 + 20.0 * rng.uniform());
        const float gp = float(4.0 * (rng.uniform() - 0.5));
        // h near 1 for most cases (0.98-1.02), else anywhere in -5..50
        const double dx = double(px) - ex, dy = double(py) - ey, dz = double(pz) - ez;
        const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
        if (!(d > 1e-6)) continue;
        const double want = n % 3 == 0 ? -5.0 + 55.0 * rng.uniform() : 0.98 + 0.04 * rng.uniform();
        const float eg = float(gp - want * R * d / (double(k) * es));
        const double h = exact_h(gp, k, px, py, pz, eg, ex, ey, ez, es, R);
        const bool says =
            penumbra_past(gp, k, px, py, pz, eg, ex, ey, ez, es, penumbra_past_scale(R));
        near += std::fabs(h - 1.0) < 1e-3;
        if (says) {
            ++past;
            least_past = std::min(least_past, h);
            // the float form the sweep evaluates (here without its vector approximations)
            ASSERT_GE(penumbra_lane(gp, k, px, py, pz, eg, ex, ey, ez, es, R), 1.0f)
                << "R " << R << " h " << h;
        }
        if (h >= 1.001) {
            ++clear;
            clear_past += says;
        }
    }
    std::printf(
        "%ld cases said past (least exact h %.7f), %ld within 1e-3 of h = 1; of %ld "
        "with h >= 1.001, %ld said past\n",
        past, least_past, near, clear, clear_past);
    EXPECT_GE(least_past, 1.0 + 1.0 / 4096.0);  // the margin: far above 1e-6 relative errors
    EXPECT_EQ(clear_past, clear);
    EXPECT_GT(near, 10000);  // (the cases do probe the boundary)
}

TEST(PenumbraPast, OnlyApplicableRadii) {
    EXPECT_FALSE(penumbra_past_applies(0.0f));  // hard shadows: the sweep's own test
    EXPECT_FALSE(penumbra_past_applies(1e-6f));
    EXPECT_TRUE(penumbra_past_applies(0.04f));
    EXPECT_FALSE(penumbra_past_applies(1e6f));
    // an edge not below P (num <= 0) is never past, whatever the distance
    EXPECT_FALSE(penumbra_past(1.0f, 1.0f, 0, 0, 1, 1.0f, 0, 0, 1.001f, 1.0f, 0.0016f));
    EXPECT_FALSE(penumbra_past(1.0f, 1.0f, 0, 0, 1, 2.0f, 0, 0, 1.001f, 1.0f, 0.0016f));
}
