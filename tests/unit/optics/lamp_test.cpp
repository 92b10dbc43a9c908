// The per-pixel lamp equations of lamp.h, by their properties, and the float instantiation
// (the runtime's rows) against the double one (the reference).

#include "deepsea/optics/lamp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace deepsea {

namespace {

/// |f - d| <= 1e-5 |d| (plus a floor for values near 0).
void expect_close(float f, double d, double floor = 1e-9) {
    EXPECT_NEAR(f, d, 1e-5 * std::fabs(d) + floor) << "float " << f << " double " << d;
}

}  // namespace

TEST(GaussianRid, OneOnTheAxisAndExpMinusHalfAtSigma) {
    const double sigma = 35.0 * M_PI / 180.0;
    EXPECT_EQ(gaussian_rid(0.0, sigma), 1.0);
    EXPECT_NEAR(gaussian_rid(sigma, sigma), std::exp(-0.5), 1e-15);
    EXPECT_NEAR(gaussian_rid(2.0 * sigma, sigma), std::exp(-2.0), 1e-15);
    EXPECT_EQ(gaussian_rid(-0.3, sigma), gaussian_rid(0.3, sigma));
}

TEST(LampAngle, ClampsRoundingBeyondOne) {
    EXPECT_EQ(lamp_angle(1.0 + 1e-12), 0.0);
    EXPECT_NEAR(lamp_angle(-1.0 - 1e-12), M_PI, 1e-15);
    EXPECT_NEAR(lamp_angle(0.5), M_PI / 3.0, 1e-15);
    EXPECT_NEAR(lamp_angle(0.5f), float(M_PI / 3.0), 1e-6f);
}

TEST(LampGeometry, ByHand) {
    // lamp at (0, 0, 0) pointing along +z, surface point P = (3, 0, 4) facing back at it
    const Vec3T<double> to_light{-3.0, 0.0, -4.0};
    const Vec3T<double> n{-0.6, 0.0, -0.8};  // towards the lamp
    const LampGeometry<double> g = lamp_geometry(to_light, n, {0.0, 0.0, 1.0});
    EXPECT_DOUBLE_EQ(g.d1, 5.0);
    EXPECT_DOUBLE_EQ(g.cos_n, 1.0);
    EXPECT_DOUBLE_EQ(g.cos_theta, 0.8);  // lamp -> P = (3, 0, 4) / 5
}

TEST(LampTerm, InverseSquareLambertAndBeerLambert) {
    const double I0 = 2.0, rid = 0.7, c = 0.3, d1 = 4.0, cos_n = 0.5;
    const double spread = lamp_spread(d1, cos_n);
    EXPECT_DOUBLE_EQ(spread, cos_n / (d1 * d1));
    EXPECT_NEAR(lamp_term(I0, rid, spread, c, d1), I0 * rid * std::exp(-c * d1) * cos_n / 16.0,
                1e-15);
    // back-facing and grazing surfaces get nothing
    EXPECT_EQ(lamp_spread(d1, -0.2), 0.0);
    EXPECT_EQ(lamp_spread(d1, 0.0), 0.0);
    // twice as far: a quarter, times the extra transmission
    const double near = lamp_term(I0, rid, lamp_spread(2.0, 1.0), c, 2.0);
    const double far = lamp_term(I0, rid, lamp_spread(4.0, 1.0), c, 4.0);
    EXPECT_NEAR(far / near, 0.25 * std::exp(-2.0 * c), 1e-15);
}

TEST(LampTerm, GaussianFormIsTheRidTimesTheLampTerm) {
    // one exponential for the Gaussian RID and the transmission: the same value in double,
    // and in float within the float form's own rounding
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 1000; ++i) {
        const double I0 = 5.0 * unit(rng), theta = unit(rng) * M_PI, sigma = 0.1 + unit(rng);
        const double spread = unit(rng), c = unit(rng), d1 = 0.3 + 12.0 * unit(rng);
        const double split = lamp_term(I0, gaussian_rid(theta, sigma), spread, c, d1);
        EXPECT_NEAR(gaussian_lamp_term(I0, theta, sigma, spread, c, d1), split, 1e-13 * split);
        expect_close(gaussian_lamp_term(float(I0), float(theta), float(sigma), float(spread),
                                        float(c), float(d1)),
                     split);
    }
    // on the axis it is the lamp term with RID 1; at theta = sigma, exp(-1/2) of that
    EXPECT_DOUBLE_EQ(gaussian_lamp_term(2.0, 0.0, 0.4, 0.1, 0.3, 4.0),
                     lamp_term(2.0, 1.0, 0.1, 0.3, 4.0));
    EXPECT_NEAR(gaussian_lamp_term(2.0, 0.4, 0.4, 0.1, 0.3, 4.0),
                std::exp(-0.5) * lamp_term(2.0, 1.0, 0.1, 0.3, 4.0), 1e-15);
}

TEST(DirectSignal, LambertianRadianceWithThePathBack) {
    // J / pi * E * exp(-c d2); clear water gives the in-air Lambertian radiance J E / pi
    EXPECT_NEAR(direct_signal(0.5, 3.0, 0.0, 7.0), 0.5 * 3.0 / M_PI, 1e-15);
    EXPECT_NEAR(direct_signal(0.5, 3.0, 0.2, 7.0), 0.5 * 3.0 / M_PI * std::exp(-1.4), 1e-15);
}

TEST(LampEquations, FloatMatchesDouble) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> pos(-2.0, 2.0), dist(0.3, 12.0), cosine(-1.0, 1.0),
        unit(0.0, 1.0);
    for (int i = 0; i < 1000; ++i) {
        const double theta = unit(rng) * M_PI, sigma = 0.1 + unit(rng);
        expect_close(gaussian_rid(float(theta), float(sigma)), gaussian_rid(theta, sigma));
        const double ct = cosine(rng);
        expect_close(lamp_angle(float(ct)), lamp_angle(ct), 1e-6);
        const Vec3T<double> w{pos(rng), pos(rng), dist(rng)}, n{pos(rng), pos(rng), -1.0};
        const Vec3T<double> a{0.3, -0.1, 0.95};
        const auto f = [](Vec3T<double> v) {
            return Vec3T<float>{float(v.x), float(v.y), float(v.z)};
        };
        const LampGeometry<double> gd = lamp_geometry(w, n, a);
        const LampGeometry<float> gf = lamp_geometry(f(w), f(n), f(a));
        expect_close(gf.d1, gd.d1);
        expect_close(gf.cos_n, gd.cos_n, 1e-6);
        expect_close(gf.cos_theta, gd.cos_theta, 1e-6);
        const double I0 = 5.0 * unit(rng), rid = unit(rng), c = unit(rng), d1 = dist(rng);
        const double cos_n = cosine(rng);
        const double sd = lamp_spread(d1, cos_n);
        const float sf = lamp_spread(float(d1), float(cos_n));
        expect_close(sf, sd);
        expect_close(lamp_term(float(I0), float(rid), sf, float(c), float(d1)),
                     lamp_term(I0, rid, sd, c, d1));
        expect_close(direct_signal(float(rid), float(I0), float(c), float(d1)),
                     direct_signal(rid, I0, c, d1));
    }
}

}  // namespace deepsea
