#include "deepsea/optics/multiple_scattering.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "deepsea/optics/backscatter.h"

namespace deepsea {

namespace {

Rig isotropic_lamp(const Vec3& at) {
    Light L;
    L.position = at;
    L.rid.sigma_deg = 1e9;  // Gaussian this wide is 1 everywhere: isotropic
    return Rig{"iso", {L}};
}

Water water(double c, double b, Phase phase) {
    Water w;
    w.c = Rgb(c);
    w.b = Rgb(b);
    w.phase = phase;
    return w;
}

/// Net outward flux of scattered light through the sphere of radius R around an isotropic
/// lamp, from scattered_radiance at one point (by symmetry): 4 pi R^2 times the integral over
/// directions of L(X, d) (-d . n). Mean and standard error.
std::pair<double, double> scattered_flux(const Transport& tr, double R, int n, Rng& rng) {
    const Vec3 X(0, 0, R), normal(0, 0, 1);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const PhaseSample ps = tr.any_direction(X, rng);
        const double f = 4.0 * M_PI * R * R * tr.scattered_radiance(X, ps.direction, rng).r *
                         -dot(ps.direction, normal) * ps.weight;
        sum += f;
        sum2 += f * f;
    }
    const double mean = sum / n;
    return {mean, std::sqrt((sum2 / n - mean * mean) / n)};
}

}  // namespace

TEST(MultipleScattering, ConservesEnergyInWaterThatOnlyScatters) {
    // Without absorption the power leaving a sphere around the lamp is the lamp's power P:
    // the unscattered part P exp(-b R) and the scattered part P (1 - exp(-b R)), all orders.
    // The net flux is a difference of outgoing and incoming light, and Petzold's forward peak
    // (1e5 times its side value) makes single paths carry much: its standard error is larger.
    for (const auto& [p, max_se] : {std::pair{Phase{PhaseKind::Isotropic, 0.0}, 0.05},
                                    std::pair{Phase{PhaseKind::HenyeyGreenstein, 0.9}, 0.05},
                                    std::pair{Phase{PhaseKind::PetzoldCoastal, 0.0}, 0.12}}) {
        const double b = 0.5, R = 2.0;
        const Transport tr(isotropic_lamp({0, 0, 0}), water(b, b, p));
        Rng rng(3);
        const double expected = 4.0 * M_PI * (1.0 - std::exp(-b * R));  // 1 W/sr everywhere
        const auto [flux, se] = scattered_flux(tr, R, 60000, rng);
        EXPECT_LT(se / expected, max_se) << to_string(p.kind);
        EXPECT_NEAR(flux / expected, 1.0, 4.0 * se / expected) << to_string(p.kind);
        std::printf("%-18s scattered flux / P (1 - exp(-b R)) = %.4f +- %.4f\n", to_string(p.kind),
                    flux / expected, se / expected);
    }
}

TEST(MultipleScattering, HigherOrdersVanishAsScatteringGoesToZero) {
    // Orders >= 2 scale as b^2 while single scattering scales as b: their ratio halves with b.
    Rig rig = isotropic_lamp({0.5, 0, 0});
    const Vec3 dir = normalize(Vec3(0.1, 0.05, 1));
    const std::vector<double> t{0.0, 1.0, 4.0, 12.0};
    const auto ratio = [&](double b) {
        const Water w = water(0.3, b, Phase{PhaseKind::HenyeyGreenstein, 0.5});
        const Transport tr(rig, w);
        const Estimate ms = higher_orders_cumulative(tr, dir, t, MonteCarlo{20000, 5}, 0);
        const Rgb ss = backscatter_integral(rig, w, dir, 0.0, t.back()).value;
        return ms.value.back().r / ss.r;
    };
    const double r1 = ratio(0.02), r2 = ratio(0.01);
    EXPECT_GT(r1, 0.0);
    EXPECT_NEAR(r1 / r2, 2.0, 0.15);
}

TEST(MultipleScattering, CumulativeIsMonotoneWithHonestErrors) {
    const Rig rig = isotropic_lamp({0.5, 0, 0});
    const Water w = water(0.3, 0.2, Phase{PhaseKind::HenyeyGreenstein, 0.9});
    const Transport tr(rig, w);
    const std::vector<double> t{0.0, 0.5, 1.0, 2.0, 4.0, 8.0};
    const Vec3 dir(0, 0, 1);
    const Estimate a = higher_orders_cumulative(tr, dir, t, MonteCarlo{20000, 1}, 0);
    for (std::size_t k = 1; k < t.size(); ++k) {
        EXPECT_GE(a.value[k].r, a.value[k - 1].r);
    }
    // Independent streams agree within their combined standard errors (5 sigma).
    const Estimate b = higher_orders_cumulative(tr, dir, t, MonteCarlo{20000, 2}, 0);
    const double diff = std::fabs(a.value.back().r - b.value.back().r);
    const double se = std::hypot(a.std_error.back().r, b.std_error.back().r);
    EXPECT_GT(se, 0.0);
    EXPECT_LT(diff, 5.0 * se);
    EXPECT_LT(se / a.value.back().r, 0.1);
}

TEST(MultipleScattering, RouletteLeavesTheNextEventOfTheChosenSegmentAlone) {
    // The AUV rig of docs/model.md's validation (a lamp 0.7 m above and 0.2 m behind the
    // camera) in coastal water. A direction drawn from a lamp's cone at a small phase function
    // value has a small weight and a segment that passes close to the lamp; when the roulette
    // came before that segment's next event, the paths that survived it carried the lamp's
    // glow times 1 / weight, and single paths 2000-36000 x their column's mean (docs/
    // ms-columns.md, "Bright paths pooled"). Columns of the 160x120 camera's lower left and
    // two others, three seeds each, 16384 paths: the median relative standard error at 20 m
    // was 14.5 % (mean 18 %) with the roulette first, 4.8 % (mean 5.4 %) after the next event.
    Light top, side;
    top.position = Vec3(0, -0.7, -0.2);
    top.direction = normalize(Vec3(0, 0.25, 1));
    top.rid.sigma_deg = 20;
    side.position = Vec3(0.6, 0, 0);
    side.direction = normalize(Vec3(-0.2, 0, 1));
    side.intensity = Rgb(1.0, 0.8, 0.6);
    side.rid.sigma_deg = 15;
    Water w = water(0.35, 0.3, Phase{PhaseKind::HenyeyGreenstein, 0.9});
    w.c = Rgb(0.6, 0.4, 0.35);
    const Transport tr(Rig{"auv", {top, side}}, w);
    const double f = 126.79232614245014, cx = 79.5, cy = 59.5;
    std::vector<double> rel;
    for (const auto& [u, v] : {std::pair{0, 96}, {8, 96}, {0, 104}, {40, 60}, {120, 20}}) {
        const Vec3 dir = normalize(Vec3((u - cx) / f, (v - cy) / f, 1.0));
        const std::vector<double> t{1.0 / dir.z, 5.0 / dir.z, 20.0 / dir.z};
        for (std::uint64_t seed = 1; seed <= 3; ++seed) {
            const Estimate e =
                higher_orders_cumulative(tr, dir, t, MonteCarlo{16384, seed}, 120 * u + v);
            ASSERT_GT(e.value.back().b, 0.0);
            rel.push_back(e.std_error.back().b / e.value.back().b);
        }
    }
    std::sort(rel.begin(), rel.end());
    std::printf("relative standard error at 20 m: median %.2f %%, worst %.2f %%\n",
                100.0 * rel[rel.size() / 2], 100.0 * rel.back());
    EXPECT_LT(rel[rel.size() / 2], 0.08);
    EXPECT_LT(rel.back(), 0.25);
}

TEST(MultipleScattering, TailIsThePathsLightAboveTheThreshold) {
    const Rig rig = isotropic_lamp({0.5, 0, 0});
    const Water w = water(0.3, 0.2, Phase{PhaseKind::HenyeyGreenstein, 0.9});
    const Transport tr(rig, w);
    const std::vector<double> t{0.5, 1.0, 2.0, 4.0, 8.0};
    const Vec3 dir(0, 0, 1);
    const auto run = [&](double above) {
        MonteCarlo mc{4000, 3};
        mc.tail_above = Rgb(above);
        return higher_orders_cumulative(tr, dir, t, mc, 0);
    };
    const Estimate plain = run(0.0);
    EXPECT_TRUE(plain.tail.empty());
    const double mean = plain.value.back().r;
    const Estimate all = run(1e-300), none = run(1e300);
    const Estimate low = run(4.0 * mean), high = run(64.0 * mean);
    for (std::size_t k = 0; k < t.size(); ++k) {
        // The split leaves the estimate as it was (the same paths).
        EXPECT_EQ(low.value[k].r, plain.value[k].r);
        EXPECT_NEAR(all.tail[k].r, plain.value[k].r, 1e-9 * mean);
        EXPECT_EQ(none.tail[k].r, 0.0);
        EXPECT_GE(low.tail[k].r, high.tail[k].r);
        EXPECT_LE(low.tail[k].r, low.value[k].r);
    }
    // Paths' totals spread far above their mean: some light lies above 4x it, less above 64x.
    EXPECT_GT(low.tail.back().r, 0.0);
    EXPECT_LT(low.tail.back().r, low.value.back().r);
    EXPECT_GT(low.tail.back().r, high.tail.back().r);
}

TEST(MultipleScattering, TailOfMeanSetsTheThresholdFromTheEstimate) {
    const Rig rig = isotropic_lamp({0.5, 0, 0});
    const Water w = water(0.3, 0.2, Phase{PhaseKind::HenyeyGreenstein, 0.9});
    const Transport tr(rig, w);
    const std::vector<double> t{0.5, 1.0, 2.0, 4.0, 8.0};
    const Vec3 dir(0, 0, 1);
    const auto run = [&](double above, double of_mean) {
        MonteCarlo mc{4000, 3};
        mc.tail_above = Rgb(above);
        mc.tail_of_mean = of_mean;
        return higher_orders_cumulative(tr, dir, t, mc, 0);
    };
    const Estimate fixed = run(16.0 * run(0.0, 0.0).value.back().r, 0.0);
    // A threshold below 16 x the mean is raised to it: the same split as that fixed threshold,
    // from the paths traced again; one above it is kept.
    const Estimate own = run(1e-300, 16.0), higher = run(1e300, 16.0);
    for (std::size_t k = 0; k < t.size(); ++k) {
        EXPECT_EQ(own.value[k].r, fixed.value[k].r);
        EXPECT_NEAR(own.tail[k].r, fixed.tail[k].r, 1e-12 * fixed.value.back().r);
        EXPECT_EQ(higher.tail[k].r, 0.0);
    }
    EXPECT_GT(own.tail.back().r, 0.0);
}

}  // namespace deepsea
