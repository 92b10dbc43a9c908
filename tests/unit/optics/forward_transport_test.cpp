// The forward scatter from transport (forward_transport.h): single scattering against its
// integral by quadrature, near-straight scattering against absorption alone (no light lost
// sideways), clear water against the small-angle model, and the fit the runtime blurs with.

#include "deepsea/optics/forward_transport.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "deepsea/optics/forward_psf.h"

namespace deepsea {

namespace {

Water water_of(Rgb c, Rgb b, double g) {
    Water w;
    w.c = c;
    w.b = b;
    w.phase = {PhaseKind::HenyeyGreenstein, g};
    w.forward = phase_function_forward_scatter();
    return w;
}

/// Once-scattered light from a uniform Lambertian plane at depth d seen along its normal, by
/// quadrature: integral_0^d b exp(-c t) integral_0^{pi/2} 2 pi sin(th) p(th)
/// exp(-c (d - t) / cos(th)) dth dt, counting only the light reaching the plane within the
/// apparent angle psi_max from the camera (hit at (d - t) tan(th), seen at atan(that / d)).
double single_scattering(const Water& w, int ch, double d, double psi_max) {
    const int nt = 60, nth = 1500;
    double sum = 0.0;
    for (int i = 0; i < nt; ++i) {
        const double t = (i + 0.5) * d / nt;
        const double lever = d - t;
        double inner = 0.0, th_prev = 0.0, f_prev = 0.0;
        for (int j = 1; j <= nth; ++j) {
            // dense near 0, where the forward peak is
            const double th = M_PI / 2 * std::pow(double(j) / nth, 3.0);
            const bool seen = std::atan(lever * std::tan(th) / d) <= psi_max;
            const double f = seen ? 2 * M_PI * std::sin(th) * w.phase(std::cos(th)) *
                                        std::exp(-w.c[ch] * lever / std::cos(th))
                                  : 0.0;
            inner += 0.5 * (f + f_prev) * (th - th_prev);
            th_prev = th;
            f_prev = f;
        }
        sum += w.b[ch] * std::exp(-w.c[ch] * t) * inner * d / nt;
    }
    return sum;
}

/// Enclosed share of the table at depth k within ring edge e.
Rgb within(const ForwardPsfTable& t, int k, int edges) {
    Rgb s;
    for (int i = 0; i < edges; ++i) s += t.share[std::size_t(k) * t.rings() + i];
    return s;
}

}  // namespace

TEST(ForwardTransport, OrderOneIsTheSingleScatteringIntegral) {
    const Water w = water_of({1.0, 0.8, 0.5}, {0.8, 0.6, 0.3}, 0.85);
    ForwardTransportSettings s;
    s.paths = 1 << 16;
    s.max_order = 1;
    const std::vector<double> depths = {0.5, 2.0};
    const ForwardPsfTable t = trace_forward_psf(w, depths, s);
    for (int k = 0; k < 2; ++k) {
        for (const int e : {20, 36, t.rings()}) {
            const Rgb mc = within(t, k, e);
            for (int c = 0; c < 3; ++c) {
                const double exact = single_scattering(w, c, depths[k], t.ring_edge[e]);
                // 4 standard errors of the total, and the quadrature's 0.2 %
                EXPECT_NEAR(mc[c], exact, 4 * t.std_error[k][c] + 2e-3 * exact)
                    << "depth " << depths[k] << " psi " << t.ring_edge[e] << " ch " << c;
            }
        }
    }
}

TEST(ForwardTransport, NearlyStraightScatteringLosesOnlyTheAbsorbedLight) {
    // g -> 1: scattering turns no light away, so what reaches the camera is what the water
    // does not absorb, exp(-(c - b) d), and it all arrives within a few tens of mrad.
    const Water w = water_of({1.0, 0.8, 0.5}, {0.8, 0.6, 0.45}, 0.99995);
    ForwardTransportSettings s;
    s.paths = 1 << 15;
    const ForwardPsfTable t = trace_forward_psf(w, forward_psf_depths(4.0, 8), s);
    int narrow = 0;
    while (t.ring_edge[narrow] < 0.05) ++narrow;
    for (int k = 0; k < t.depths(); ++k) {
        const Rgb all = t.direct[k] + t.total(k);
        const Rgb near = within(t, k, narrow);
        for (int c = 0; c < 3; ++c) {
            const double expect = std::exp(-(w.c[c] - w.b[c]) * t.depth[k]);
            EXPECT_NEAR(all[c], expect, 4 * t.std_error[k][c] + 1e-3 * expect)
                << "depth " << t.depth[k] << " ch " << c;
            EXPECT_GT(near[c], 0.995 * t.total(k)[c]);
        }
    }
}

TEST(ForwardTransport, ClearWaterAgreesWithTheSmallAngleModel) {
    // b d <= 0.1 and absorption over the extra path of scattered light (a few tenths of a
    // metre) small: the small-angle model's assumptions hold. (At 10 m in the red, c = 0.4,
    // the model keeps 12 % too much: the scattered paths' extra length absorbs it.)
    const Water w = water_of({0.4, 0.1, 0.05}, {0.02, 0.025, 0.03}, 0.9);
    ForwardTransportSettings s;
    s.paths = 1 << 16;
    const ForwardPsfTable t = trace_forward_psf(w, {1.0, 3.0}, s);
    const ForwardSpread spread = forward_spread(w.phase, 8);
    for (int k = 0; k < t.depths(); ++k) {
        const double d = t.depth[k];
        for (const int e : {24, 32, 40, t.rings()}) {
            const Rgb mc = within(t, k, e);
            for (int c = 0; c < 3; ++c) {
                double model = 0.0, term = std::exp(-w.c[c] * d);
                for (int n = 1; n <= 8; ++n) {
                    term *= w.b[c] * d / n;
                    model +=
                        term * mixture_within(spread.sigma, spread.mass[n - 1], t.ring_edge[e]);
                }
                // within 0.3 rad to 3 %; all angles to 6 % (the wide angles' longer paths)
                const double tol = e == t.rings() ? 0.06 : 0.03;
                EXPECT_NEAR(mc[c], model, 4 * t.std_error[k][c] + tol * model)
                    << "depth " << d << " psi " << t.ring_edge[e] << " ch " << c;
            }
        }
    }
}

TEST(ForwardTransport, NothingScattersNothingSpreads) {
    const Water w = water_of({0.3, 0.2, 0.1}, {0.0, 0.0, 0.0}, 0.9);
    const ForwardPsfTable t = trace_forward_psf(w, {1.0, 3.0}, {});
    for (const Rgb& v : t.share) EXPECT_EQ(v.max(), 0.0);
    EXPECT_DOUBLE_EQ(t.direct[1].g, std::exp(-0.6));
}

TEST(ForwardTransport, SameTableAtAnyThreadCount) {
    const Water w = water_of({1.0, 0.95, 1.05}, {0.8, 0.78, 0.82}, 0.85);
    ForwardTransportSettings s;
    s.paths = 5000;
    const ForwardPsfTable a = trace_forward_psf(w, {1.0, 2.0}, s, Parallel{1});
    const ForwardPsfTable b = trace_forward_psf(w, {1.0, 2.0}, s, Parallel{2});
    for (std::size_t i = 0; i < a.share.size(); ++i) {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(a.share[i][c], b.share[i][c]);
    }
    s.seed = 2;
    const ForwardPsfTable other = trace_forward_psf(w, {1.0, 2.0}, s);
    EXPECT_NE(other.total(1).r, a.total(1).r);
}

TEST(ForwardTransport, RefusesBadSettingsAndTables) {
    const Water w = water_of({1.0, 1.0, 1.0}, {0.5, 0.5, 0.5}, 0.9);
    ForwardTransportSettings s;
    s.paths = 0;
    EXPECT_THROW(trace_forward_psf(w, {1.0}, s), ConfigError);
    EXPECT_THROW(trace_forward_psf(w, {2.0, 1.0}, {}), ConfigError);
    ForwardPsfTable t = trace_forward_psf(w, {1.0}, ForwardTransportSettings{64});
    t.share.pop_back();
    EXPECT_THROW(t.validate("t"), ConfigError);
}

TEST(ForwardPsf, FittedToATransportTableKeepsItsLight) {
    // Turbid water: each depth's weights over the pixel scales hold the table's scattered light
    // resampled to a source at that range (ring psi from the plane at depth r cos(psi), linear
    // between the table's depths), and the mixture follows the table's enclosed share.
    const Water w = water_of({1.0, 0.95, 1.05}, {0.8, 0.78, 0.82}, 0.85);
    ForwardTransportSettings s;
    s.paths = 1 << 14;
    const ForwardPsfTable t = trace_forward_psf(w, forward_psf_depths(6.0, 8), s);
    const ForwardPsf psf(t, w, 600.0, 800, 800);
    EXPECT_TRUE(psf.from_transport());
    EXPECT_LT(psf.fit_error(), 0.02);
    for (int k = 0; k < t.depths(); ++k) {
        Rgb resampled;
        for (int i = 0; i < t.rings(); ++i) {
            const double psi =
                i == 0 ? 0.5 * t.ring_edge[1] : std::sqrt(t.ring_edge[i] * t.ring_edge[i + 1]);
            const double d = t.depth[k] * std::cos(psi);
            int m = 0;
            while (m < t.depths() && t.depth[m] <= d) ++m;
            const Rgb lo = m == 0 ? Rgb() : t.share[std::size_t(m - 1) * t.rings() + i];
            const double d_lo = m == 0 ? 0.0 : t.depth[m - 1];
            const Rgb hi = t.share[std::size_t(std::min(m, t.depths() - 1)) * t.rings() + i];
            const double f = m < t.depths() ? (d - d_lo) / (t.depth[m] - d_lo) : 0.0;
            resampled += lo * (1.0 - f) + hi * f;
        }
        const Rgb sum = psf.total(t.depth[k]);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(sum[c], resampled[c], 1e-9 + 1e-6 * resampled[c]) << "depth " << t.depth[k];
    }
    // linear between depths, falling beyond the last
    const Rgb mid = psf.total(0.5 * (t.depth[2] + t.depth[3]));
    EXPECT_NEAR(mid.g, 0.5 * (psf.total(t.depth[2]).g + psf.total(t.depth[3]).g), 1e-12);
    EXPECT_LT(psf.total(8.0).g, psf.total(6.0).g);
    EXPECT_EQ(psf.total(0.0).g, 0.0);
}

}  // namespace deepsea
