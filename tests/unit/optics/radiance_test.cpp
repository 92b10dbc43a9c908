#include <gtest/gtest.h>

#include <cmath>

#include "deepsea/core/error.h"
#include "deepsea/optics/analytic.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/optics/direct.h"
#include "deepsea/optics/jerlov.h"
#include "deepsea/optics/normals.h"

namespace deepsea {

namespace {

/// An isotropic point lamp: a constant RID table over the whole sphere.
Light isotropic_lamp(const Vec3& pos, double I0) {
    Light l;
    l.position = pos;
    l.intensity = Rgb(I0);
    l.rid.kind = Rid::Kind::Table;
    l.rid.angle_deg = {0.0, 180.0};
    l.rid.value = {1.0, 1.0};
    return l;
}

Water water(Rgb c, Rgb b, Phase p) {
    Water w;
    w.c = c;
    w.b = b;
    w.phase = p;
    return w;
}

}  // namespace

TEST(Direct, OneLampByHand) {
    Rig rig;
    Light l;
    l.position = {0.5, 0.0, 0.0};
    l.direction = {0.0, 0.0, 1.0};
    l.intensity = {2.0, 1.0, 0.5};
    rig.lights.push_back(l);
    const Water w = water({0.4, 0.2, 0.1}, {0.1, 0.1, 0.1}, {});
    const Vec3 P{0.0, 0.0, 2.0}, n{0.0, 0.0, -1.0};
    const Rgb J{0.5, 0.4, 0.3};
    // d1 = sqrt(0.25 + 4), theta = atan(0.5 / 2), n . w = 2 / d1
    const double d1 = std::sqrt(4.25), theta = std::atan2(0.5, 2.0), s = 35.0 * M_PI / 180.0;
    const double geo = std::exp(-theta * theta / (2 * s * s)) * (2.0 / d1) / (d1 * d1);
    const Rgb D = direct_radiance(rig, w, P, n, J);
    for (int c = 0; c < 3; ++c) {
        const double expect = J[c] / M_PI * l.intensity[c] * geo * std::exp(-w.c[c] * (d1 + 2.0));
        EXPECT_NEAR(D[c], expect, 1e-12 * expect);
    }
}

TEST(Direct, TwoLampsAddAndBackFacingLampsGiveNothing) {
    Rig one, two;
    one.lights.push_back(isotropic_lamp({-0.5, 0, 0}, 1.0));
    two = one;
    two.lights.push_back(isotropic_lamp({0.5, 0, 0}, 1.0));
    const Water w = water(Rgb(0.3), Rgb(0.1), {});
    const Vec3 P{0, 0, 3}, n{0, 0, -1};
    EXPECT_NEAR(direct_radiance(two, w, P, n, Rgb(1)).g,
                2.0 * direct_radiance(one, w, P, n, Rgb(1)).g, 1e-15);
    EXPECT_EQ(direct_radiance(two, w, P, Vec3(0, 0, 1), Rgb(1)).g, 0.0);
}

TEST(Direct, ZeroScatteringIsBeerLambert) {
    // Lamp at the camera, pointing at a fronto-parallel wall: D = J/pi I0 exp(-2 c d) / d^2.
    Rig rig;
    rig.lights.push_back(isotropic_lamp({0, 0, 0}, 3.0));
    for (double d : {1.0, 4.0, 10.0}) {
        const Water w = water({0.5, 0.25, 0.1}, Rgb(0.0), {});
        const Rgb D = direct_radiance(rig, w, {0, 0, d}, {0, 0, -1}, Rgb(1.0));
        for (int c = 0; c < 3; ++c) {
            const double expect = 3.0 / M_PI * std::exp(-2.0 * w.c[c] * d) / (d * d);
            EXPECT_NEAR(D[c], expect, 1e-13 * expect);
        }
        const Integral B = backscatter_integral(rig, w, {0, 0, 1}, 0.0, d);
        EXPECT_EQ(B.value.max(), 0.0);
    }
}

TEST(Backscatter, MatchesSun2005ClosedForm) {
    // Isotropic point lamp, isotropic phase: Sun, Ramamoorthi, Narasimhan, Nayar 2005.
    struct Case {
        Vec3 lamp;
        double c, b, range;
    };
    const Case cases[] = {{{0.5, 0.0, 0.0}, 0.3, 0.3, 5.0},
                          {{1.0, -0.3, 0.4}, 0.2, 0.1, 8.0},
                          {{-0.4, 0.2, -0.2}, 1.0, 0.6, 3.0},
                          {{0.0, 2.0, 1.0}, 0.05, 0.02, 20.0}};
    const Vec3 dir = normalize(Vec3(0.1, -0.05, 1.0));
    for (const Case& k : cases) {
        Rig rig;
        rig.lights.push_back(isotropic_lamp(k.lamp, 2.0));
        const Water w = water(Rgb(k.c), Rgb(k.b), Phase{PhaseKind::Isotropic});
        const double D = length(k.lamp);
        const double gamma = std::acos(dot(k.lamp / D, dir));
        const double expect = sun2005_airlight(k.c, k.b, 2.0, D, gamma, k.range);
        Quadrature q;
        q.rel_tol = 1e-9;
        const double got = backscatter_integral(rig, w, dir, 0.0, k.range, q).value.g;
        EXPECT_NEAR(got, expect, 1e-6 * expect) << "lamp " << k.lamp.x << " c " << k.c;
        // and the default tolerance is well inside 1e-4
        EXPECT_NEAR(backscatter_integral(rig, w, dir, 0.0, k.range).value.g, expect, 1e-5 * expect);
    }
}

TEST(Backscatter, CumulativeIsMonotoneAndSumsTheSegments) {
    Rig rig;
    Light l;
    l.position = {0.5, 0, 0};
    l.direction = normalize(Vec3(-0.5, 0, 1));
    rig.lights.push_back(l);
    const Water w = jerlov_water("IB");
    const Vec3 dir = normalize(Vec3(0.2, 0.1, 1));
    const std::vector<double> t{0.0, 0.5, 1.0, 2.0, 4.0, 8.0};
    Quadrature q;
    q.rel_tol = 1e-9;
    const auto cum = backscatter_cumulative(rig, w, dir, t, q);
    EXPECT_EQ(cum[0].max(), 0.0);
    for (std::size_t k = 1; k < t.size(); ++k) {
        EXPECT_GT(cum[k].g, cum[k - 1].g);
        const double direct = backscatter_integral(rig, w, dir, 0.0, t[k], q).value.g;
        EXPECT_NEAR(cum[k].g, direct, 1e-8 * direct);
    }
}

TEST(Backscatter, LongerPathInTheCornersNotShorter) {
    // The integral runs in path length t = z / cos(phi): an off-axis ray to the same planar
    // depth collects over a longer path than the paper's dz*cos(phi) weighting assumes.
    Rig rig;
    rig.lights.push_back(isotropic_lamp({0, 0, 0}, 1.0));
    const Water w = water(Rgb(0.0001), Rgb(0.0001), Phase{PhaseKind::Isotropic});
    const Vec3 axis{0, 0, 1}, corner = normalize(Vec3(1, 1, 1));
    // lamp at the camera: in-scatter per metre is b/(4 pi) / t^2 -> integral from 1 m
    const double z = 3.0, t_corner = z * std::sqrt(3.0);
    const double on = backscatter_integral(rig, w, axis, 1.0, z).value.g;
    const double off = backscatter_integral(rig, w, corner, 1.0, t_corner).value.g;
    EXPECT_GT(off, on);
}

TEST(Normals, TiltedPlaneGivesItsTrueNormal) {
    const Camera cam{40, 30, 35, 35, 19.5, 14.5};
    // plane n . X = -3 with n = normalize(0.3, -0.2, -1)
    const Vec3 n = normalize(Vec3(0.3, -0.2, -1.0));
    Image z(cam.width, cam.height, 1);
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) z.at(u, v) = float(-3.0 / dot(n, cam.ray(u, v)));
    }
    for (int v : {0, 7, cam.height - 1}) {
        for (int u : {0, 20, cam.width - 1}) {
            const Vec3 got = surface_normal(cam, z, u, v);
            EXPECT_NEAR(length(got - n), 0.0, 2e-5) << u << "," << v;  // float depth
        }
    }
}

TEST(Normals, OneSidedAtDiscontinuitiesAndOpenWater) {
    const Camera cam{20, 10, 20, 20, 9.5, 4.5};
    Image z(cam.width, cam.height, 1, 2.0f);
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 10; u < cam.width; ++u) z.at(u, v) = 5.0f;  // a step at u = 10
    }
    z.at(3, 3) = std::nanf("");
    // both sides of the step and next to the NaN still see a flat wall facing the camera
    for (int u : {9, 10, 2, 4}) {
        const Vec3 n = surface_normal(cam, z, u, 3);
        EXPECT_NEAR(n.z, -1.0, 1e-9) << u;
    }
    EXPECT_EQ(surface_normal(cam, z, 3, 3).z, -1.0);
}

TEST(Jerlov, PresetsArePhysicalAndUnknownTypesThrow) {
    for (const auto& t : jerlov_types()) {
        const Water w = jerlov_water(t);
        for (int c = 0; c < 3; ++c) {
            EXPECT_GT(w.b[c], 0.0);
            EXPECT_LE(w.b[c], w.c[c]);
        }
        EXPECT_GT(w.c.r, w.c.g) << t;  // red is absorbed most
    }
    EXPECT_LT(jerlov_water("IB").c.g, jerlov_water("5C").c.g);
    EXPECT_THROW(jerlov_water("IV"), ConfigError);
}

TEST(ForwardScatter, DefaultsAreWithinTheirRanges) {
    const Water w = jerlov_water("3C");
    const ForwardScatter fs = default_forward_scatter(w);
    EXPECT_TRUE(fs.enabled);
    for (int c = 0; c < 3; ++c) {
        EXPECT_LE(fs.G[c], w.c[c]);
        EXPECT_GE(fs.G[c], w.c[c] - w.b[c]);
    }
    EXPECT_GT(fs.k, 0.0);
    EXPECT_LT(fs.k, 0.05);
}

}  // namespace deepsea

namespace deepsea {

// The figures quoted in docs/model.md.
TEST(ForwardScatter, JerlovIBDefaultsAsDocumented) {
    const ForwardScatter fs = default_forward_scatter(jerlov_water("IB"));
    EXPECT_NEAR(fs.G.r, 0.42, 0.005);
    EXPECT_NEAR(fs.G.g, 0.13, 0.005);
    EXPECT_NEAR(fs.G.b, 0.10, 0.005);
    EXPECT_NEAR(fs.k, 1.4e-3, 0.05e-3);
    EXPECT_NEAR(Phase{PhaseKind::PetzoldClear}.mean_cosine(), 0.87, 0.005);
    EXPECT_NEAR(Phase{PhaseKind::PetzoldCoastal}.mean_cosine(), 0.94, 0.005);
    EXPECT_NEAR(Phase{PhaseKind::PetzoldTurbid}.mean_cosine(), 0.92, 0.005);
}

}  // namespace deepsea
