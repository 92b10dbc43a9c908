#include "deepsea/optics/phase_sampling.h"

#include <gtest/gtest.h>

#include <cmath>

#include "deepsea/core/random.h"

namespace deepsea {

namespace {

/// Weighted Monte Carlo moments of sampled cos(psi): E[w], E[w cos], E[w cos^2].
struct Moments {
    double w = 0.0, cos = 0.0, cos2 = 0.0;
};

Moments moments(const Phase& p, int n) {
    const PhaseSampler s(p);
    Moments m;
    for (int i = 0; i < n; ++i) {
        double w = 0.0;
        const double c = s.sample_cos((i + 0.5) / n, w);  // stratified
        m.w += w / n;
        m.cos += w * c / n;
        m.cos2 += w * c * c / n;
    }
    return m;
}

}  // namespace

TEST(PhaseSampling, SamplesHaveThePhaseFunctionsMeanCosine) {
    for (PhaseKind k : {PhaseKind::Isotropic, PhaseKind::HenyeyGreenstein, PhaseKind::PetzoldClear,
                        PhaseKind::PetzoldCoastal, PhaseKind::PetzoldTurbid}) {
        const Phase p{k, 0.9};
        const Moments m = moments(p, 400000);
        EXPECT_NEAR(m.w, 1.0, 2e-3) << to_string(k);
        EXPECT_NEAR(m.cos, p.mean_cosine(), 2e-3) << to_string(k);
    }
}

TEST(PhaseSampling, HenyeyGreensteinSecondMomentIsAnalytic) {
    // For HG, <cos^2 psi> = (1 + 2 g^2) / 3.
    for (double g : {-0.5, 0.3, 0.9}) {
        const Moments m = moments(Phase{PhaseKind::HenyeyGreenstein, g}, 400000);
        EXPECT_NEAR(m.cos2, (1.0 + 2.0 * g * g) / 3.0, 1e-3) << g;
    }
}

TEST(PhaseSampling, DirectionsHaveTheSampledAngleAndUnitLength) {
    const PhaseSampler s(Phase{PhaseKind::HenyeyGreenstein, 0.7});
    Rng rng(7);
    for (const Vec3 a : {Vec3(0, 0, 1), Vec3(0, 0, -1), normalize(Vec3(1, -2, 0.3))}) {
        for (int i = 0; i < 1000; ++i) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            double w = 0.0;
            const double c = s.sample_cos(u1, w);
            const Vec3 d = s.sample(a, u1, u2).direction;
            EXPECT_NEAR(length(d), 1.0, 1e-12);
            EXPECT_NEAR(dot(d, a), c, 1e-12);
        }
    }
}

}  // namespace deepsea
