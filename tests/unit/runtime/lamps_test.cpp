#include "deepsea/runtime/lamps.h"

#include <gtest/gtest.h>

#include <random>

#include "deepsea/optics/direct.h"
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
