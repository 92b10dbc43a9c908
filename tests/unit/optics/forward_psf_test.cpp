// The forward-scatter point spread derived from the phase function (forward_psf.h): its
// kernel against a Monte Carlo of its own definition (psi = theta u), the Gaussian mixtures
// against the kernel, and the per-pixel weights against their closed-form sum.

#include "deepsea/optics/forward_psf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "deepsea/core/random.h"
#include "deepsea/optics/phase_sampling.h"
#include "deepsea/optics/water.h"

namespace deepsea {

namespace {

Phase hg(double g) { return {PhaseKind::HenyeyGreenstein, g}; }

/// Monte Carlo of the apparent angle after `orders` scatterings: each scattering angle theta
/// is drawn from the phase function (forward hemisphere only), seen at theta * u from the
/// camera, in a random azimuth; the angles add as 2-D vectors. Returns the share within each
/// radius (of all draws, so that the backward hemisphere counts as lost).
std::vector<double> sampled_within(const Phase& phase, int orders, const std::vector<double>& r,
                                   int n, std::uint64_t seed) {
    const PhaseSampler sampler(phase);
    Rng rng(seed);
    std::vector<double> within(r.size(), 0.0);
    for (int i = 0; i < n; ++i) {
        double x = 0.0, y = 0.0, weight = 1.0;
        for (int k = 0; k < orders; ++k) {
            double w = 1.0;
            const double theta = std::acos(sampler.sample_cos(rng.uniform(), w));
            weight *= theta <= M_PI / 2.0 ? w : 0.0;
            const double psi = theta * rng.uniform(), phi = 2.0 * M_PI * rng.uniform();
            x += psi * std::cos(phi);
            y += psi * std::sin(phi);
        }
        const double psi = std::hypot(x, y);
        for (std::size_t j = 0; j < r.size(); ++j) within[j] += psi <= r[j] ? weight / n : 0.0;
    }
    return within;
}

const std::vector<double> kRadii = {1e-3, 3e-3, 0.01, 0.03, 0.1, 0.3, 1.0};

}  // namespace

TEST(ForwardPsf, KernelHoldsTheForwardHemisphere) {
    for (const Phase& p : {Phase{}, hg(0.9), hg(0.5), Phase{PhaseKind::PetzoldCoastal, 0.0}}) {
        EXPECT_NEAR(forward_kernel_within(p, M_PI / 2.0), p.fraction_within(M_PI / 2.0), 2e-3)
            << to_string(p.kind) << " g " << p.g;
    }
    EXPECT_NEAR(forward_kernel_within(Phase{}, M_PI / 2.0), 0.5, 2e-3);
    EXPECT_EQ(forward_kernel(hg(0.9), 2.0), 0.0);  // backwards: not towards the camera
    EXPECT_GT(forward_kernel(hg(0.9), 0.01), forward_kernel(hg(0.9), 0.1));
}

TEST(ForwardPsf, KernelIsTheDensityOfThetaTimesAUniformShare) {
    // psi = theta u with theta ~ p and u uniform in [0, 1] has exactly the density K_1.
    for (const Phase& p : {hg(0.9), Phase{PhaseKind::PetzoldClear, 0.0}}) {
        const int n = 400000;
        const std::vector<double> mc = sampled_within(p, 1, kRadii, n, 11);
        for (std::size_t j = 0; j < kRadii.size(); ++j) {
            const double se = std::sqrt(mc[j] * (1.0 - mc[j]) / n) + 1e-4;
            EXPECT_NEAR(forward_kernel_within(p, kRadii[j]), mc[j], 4.0 * se)
                << to_string(p.kind) << " radius " << kRadii[j];
        }
    }
}

TEST(ForwardPsf, MixturesFollowTheKernelAndItsConvolutions) {
    const Phase p = hg(0.9);
    const ForwardSpread s = forward_spread(p, 3);
    const double f = forward_kernel_within(p, M_PI / 2.0);
    double m1 = 0.0, m3 = 0.0;
    for (std::size_t j = 0; j < s.sigma.size(); ++j) {
        m1 += s.mass[0][j];
        m3 += s.mass[2][j];
    }
    EXPECT_NEAR(m1, f, 1e-9);
    EXPECT_NEAR(m3, f * f * f, 1e-9);
    // K_1's mixture against the kernel itself, K_2's against a Monte Carlo of two scatterings.
    for (const double r : kRadii) {
        EXPECT_NEAR(mixture_within(s.sigma, s.mass[0], r), forward_kernel_within(p, r), 0.002)
            << "radius " << r;
    }
    const int n = 200000;
    const std::vector<double> mc = sampled_within(p, 2, kRadii, n, 12);
    for (std::size_t j = 0; j < kRadii.size(); ++j) {
        EXPECT_NEAR(mixture_within(s.sigma, s.mass[1], kRadii[j]), mc[j], 0.005)
            << "radius " << kRadii[j];
    }
}

TEST(ForwardPsf, WeightsSumToTheForwardShareOfAllOrders) {
    Water w;
    w.c = {0.49, 0.2, 0.18};
    w.b = {0.11, 0.12, 0.14};
    w.phase = hg(0.9);
    const ForwardPsf psf(w, 600.0, 800, 600);
    ASSERT_EQ(psf.scales(), 12);  // 0, 1, 2, ..., 512, 800 px
    EXPECT_EQ(psf.sigma_px(0), 0.0);
    EXPECT_EQ(psf.sigma_px(10), 512.0);
    EXPECT_EQ(psf.sigma_px(11), 800.0);
    const double f = forward_kernel_within(w.phase, M_PI / 2.0);
    for (const double d : {0.0, 0.5, 3.0, 20.0, 200.0}) {
        const Rgb t = psf.total(d);
        for (int ch = 0; ch < 3; ++ch) {
            const double expected = std::exp(-w.c[ch] * d) * std::expm1(f * w.b[ch] * d);
            EXPECT_NEAR(t[ch], expected, 1e-9 * std::exp(-(w.c[ch] - w.b[ch]) * d) + 1e-300)
                << "d " << d << " channel " << ch;
        }
        for (int j = 0; j < psf.scales(); ++j) EXPECT_GE(psf.weight(j, d).g, 0.0);
    }
    // Farther surfaces spread wider: the mean scale grows with d.
    const auto mean_scale = [&](double d) {
        double num = 0.0, den = 0.0;
        for (int j = 0; j < psf.scales(); ++j) {
            num += j * psf.weight(j, d).g;
            den += psf.weight(j, d).g;
        }
        return num / den;
    };
    EXPECT_LT(mean_scale(1.0), mean_scale(10.0));
    EXPECT_LT(mean_scale(10.0), mean_scale(40.0));
}

}  // namespace deepsea
