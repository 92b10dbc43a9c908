#include "deepsea/runtime/lamps.h"

#include <gtest/gtest.h>

#include <random>

#include "deepsea/core/error.h"
#include "deepsea/optics/direct.h"
#include "deepsea/optics/lamp_field.h"
#include "runtime_fixtures.h"

namespace deepsea {

// The vectorised float row must give the optics layer's lamp_irradiance (double) to 1e-5.
void expect_rows_match(const Rig& rig, const Water& water) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> xy(-2.0f, 2.0f), zz(0.5f, 9.0f), nn(-0.5f, 0.5f);
    const int n = 257;
    std::vector<float> x(n), y(n), z(n), nx(n), ny(n), nz(n), e(3 * n);
    for (int u = 0; u < n; ++u) {
        x[u] = xy(rng);
        y[u] = xy(rng);
        z[u] = u % 17 == 0 ? 0.0f : zz(rng);  // z == 0: open water, no light
        const Vec3 nrm = normalize(Vec3(nn(rng), nn(rng), -1.0));
        nx[u] = float(nrm.x);
        ny[u] = float(nrm.y);
        nz[u] = float(nrm.z);
    }
    const AnalyticLamps lamps(rig, water);
    lamps.irradiance_row({0, n, x.data(), y.data(), z.data(), nx.data(), ny.data(), nz.data()},
                         e.data());
    for (int u = 0; u < n; ++u) {
        const Rgb ref = z[u] > 0.0f ? lamp_irradiance(rig, water, Vec3(x[u], y[u], z[u]),
                                                      Vec3(nx[u], ny[u], nz[u]))
                                    : Rgb(0.0);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(e[c * n + u], ref[c], 1e-5 * std::max(ref[c], 1e-3)) << "pixel " << u;
        }
    }
}

TEST(AnalyticLamps, GaussianLampsMatchOptics) {
    expect_rows_match(testing::two_lamps(), jerlov_water("IB"));
}

TEST(AnalyticLamps, TabulatedRidAndCutoffMatchOptics) {
    Rig rig = testing::two_lamps();
    rig.lights[0].rid.kind = Rid::Kind::Table;
    rig.lights[0].rid.angle_deg = {0, 10, 30, 60};
    rig.lights[0].rid.value = {1.0, 0.9, 0.4, 0.05};
    rig.lights[1].rid.cutoff_deg = 25.0;
    expect_rows_match(rig, jerlov_water("3C"));
}

}  // namespace deepsea

namespace deepsea {

// With lamp fields, a row adds each lamp's scattered light: the float row against the
// unscattered optics term plus the double evaluation of the same table in the lamp's frame.
TEST(AnalyticLamps, ScatteredLightFromLampFieldsMatchesTheScalarTable) {
    const Rig rig = testing::two_lamps();
    const Water water = jerlov_water("3C");
    LampFieldSettings s;
    s.nr = 10;
    s.ntheta = 13;
    s.r0 = 0.05;
    s.r_max = 12.0;
    s.samples = 64;  // noise does not matter here: both sides read the same table
    std::vector<LampField> fields;
    for (const Light& L : rig.lights) fields.push_back(bake_lamp_field(L, water, s));
    const int n = 129;
    std::vector<float> x(n), y(n), z(n), nx(n), ny(n), nz(n), e(3 * n), e0(3 * n);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> xy(-2.0f, 2.0f), zz(0.5f, 9.0f), nn(-0.5f, 0.5f);
    for (int u = 0; u < n; ++u) {
        x[u] = xy(rng);
        y[u] = xy(rng);
        z[u] = u % 11 == 0 ? 0.0f : zz(rng);
        const Vec3 nrm = normalize(Vec3(nn(rng), nn(rng), -1.0));
        nx[u] = float(nrm.x);
        ny[u] = float(nrm.y);
        nz[u] = float(nrm.z);
    }
    const RowGeometry row{0, n, x.data(), y.data(), z.data(), nx.data(), ny.data(), nz.data()};
    AnalyticLamps(rig, water).irradiance_row(row, e0.data());
    AnalyticLamps(rig, water, fields).irradiance_row(row, e.data());
    double scattered_total = 0.0;
    for (int u = 0; u < n; ++u) {
        Rgb expect;
        if (z[u] > 0.0f) {
            const Vec3 P(x[u], y[u], z[u]), N(nx[u], ny[u], nz[u]);
            for (std::size_t l = 0; l < rig.lights.size(); ++l) {
                const Light& L = rig.lights[l];
                Vec3 ex, ey;
                lamp_frame(L.direction, ex, ey);
                const Vec3 p = P - L.position;
                double s3[3];
                lamp_field_irradiance(LampFieldView<double>(fields[l]), dot(p, ex), dot(p, ey),
                                      dot(p, L.direction), dot(N, ex), dot(N, ey),
                                      dot(N, L.direction), s3[0], s3[1], s3[2]);
                expect += Rgb(s3[0], s3[1], s3[2]) * L.intensity;
            }
        }
        for (int c = 0; c < 3; ++c) {
            const double got = e[c * n + u] - e0[c * n + u];
            EXPECT_NEAR(got, expect[c], 1e-4 * std::max(expect[c], 1e-3)) << "pixel " << u;
            scattered_total += got;
        }
    }
    EXPECT_GT(scattered_total, 0.0);
}

TEST(AnalyticLamps, LampFieldsMustMatchTheLamps) {
    EXPECT_THROW(AnalyticLamps(testing::two_lamps(), jerlov_water("IB"), std::vector<LampField>(1)),
                 AssetError);
}

}  // namespace deepsea
