// Marine snow lit by a multiple-scattering asset's lamp fields (runtime/snow_light.h with
// fields; optics' particle_radiance with fields in double): the float rows against the double
// equation, and the particles' added light in a drawn frame.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "deepsea/core/random.h"
#include "deepsea/optics/transmission.h"
#include "deepsea/runtime/marine_snow.h"
#include "deepsea/runtime/snow_light.h"
#include "snow_fixtures.h"

namespace deepsea {

namespace {

Water water() {
    Water w;
    w.c = {0.6, 0.45, 0.5};
    w.b = {0.4, 0.4, 0.4};
    w.phase = Phase{PhaseKind::HenyeyGreenstein, 0.85};
    return w;
}

/// Small, noisy tables: the test compares two evaluations of the same table.
std::vector<LampField> fields(const Rig& r, const Water& w) {
    LampFieldSettings s;
    s.nr = 12;
    s.ntheta = 10;
    s.r0 = 0.05;
    s.r_max = 8.0;
    s.samples = 128;
    std::vector<LampField> out;
    for (const Light& L : r.lights) out.push_back(bake_lamp_field(L, w, s));
    return out;
}

}  // namespace

TEST(SnowScatteredLight, FloatRowsMatchParticleRadianceWithFields) {
    const Camera cam = testing::snow_camera();
    const Water wat = water();
    const Rig r = testing::snow_lamps(false);
    const std::vector<LampField> scattered = fields(r, wat);
    Rng rng(3);
    const int n = 203;
    const testing::ParticleSet ps = testing::random_particles(rng, n, 3.5);
    const std::vector<Vec3>& X = ps.X;
    const std::vector<float>& D = ps.D;
    for (const Phase phase :
         {Phase{PhaseKind::Isotropic, 0.0}, Phase{PhaseKind::HenyeyGreenstein, 0.6},
          Phase{PhaseKind::PetzoldTurbid, 0.0}}) {
        Snow snow = snow_preset("plume");
        snow.phase = phase;
        std::vector<float> e(3 * std::size_t(n)), e0(3 * std::size_t(n)),
            scratch(5 * std::size_t(n));
        float* s = scratch.data();
        const SnowLightScratch sc{s, s + n, s + 2 * n, s + 3 * n, s + 4 * n};
        const ParticleRows rows = ps.rows();
        snow_light(r, wat, snow, cam.fx, cam.fy, rows, e.data(), e.data() + n, e.data() + 2 * n, sc,
                   scattered);
        snow_light(r, wat, snow, cam.fx, cam.fy, rows, e0.data(), e0.data() + n, e0.data() + 2 * n,
                   sc);
        double added = 0, direct = 0;
        for (int q = 0; q < n; ++q) {
            const Vec3& p = X[std::size_t(q)];
            const double d2 = length(p), Dq = double(D[std::size_t(q)]);
            const double area = M_PI / 4 * Dq * Dq * cam.fx * cam.fy * d2 / std::pow(p.z, 3);
            const Rgb L =
                particle_radiance(r, wat, snow, p, scattered) * transmission(wat.c, d2) * area;
            const double want[3] = {L.r, L.g, L.b};
            const double scale = std::max({want[0], want[1], want[2]});
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = std::size_t(c * n + q);
                EXPECT_NEAR(e[i], want[c], 2e-4 * scale + 1e-30)
                    << "phase " << int(phase.kind) << " particle " << q;
                added += e[i] - e0[i];
                direct += e0[i];
                EXPECT_GE(e[i], e0[i]);  // the scattered light only adds
            }
        }
        // In this turbid water (b / c 0.7-0.9) the lamps' scattered light is a large part of
        // what particles outside the beams receive.
        EXPECT_GT(added, 0.05 * direct) << int(phase.kind);
    }
    // One field per lamp, or none.
    std::vector<float> e(3 * 4), sc(5 * 4);
    const ParticleRows rows{1, ps.x.data(), ps.y.data(), ps.z.data(), ps.inv.data(), ps.D.data()};
    EXPECT_THROW(
        snow_light(r, wat, snow_preset("plume"), 1, 1, rows, e.data(), e.data() + 1, e.data() + 2,
                   {sc.data(), sc.data() + 1, sc.data() + 2, sc.data() + 3, sc.data() + 4},
                   std::vector<LampField>(1)),
        std::invalid_argument);
}

TEST(SnowScatteredLight, DrawnFrameGainsTheScatteredLight) {
    const Camera cam = testing::snow_camera();
    const Water wat = water();
    const Rig r = testing::snow_lamps(false);
    SnowSettings st;
    st.snow = snow_preset("nepheloid");
    const Image depth(cam.width, cam.height, 1, 3.0f);
    const auto draw = [&](std::vector<LampField> f) {
        MarineSnow snow(st, r, wat, std::move(f));
        snow.set_frame(7, std::nullopt);
        Image final(cam.width, cam.height, 3, 0.0f), layer(cam.width, cam.height, 3, 0.0f);
        snow.draw(cam, depth, final, &layer, nullptr);
        double sum = 0;
        for (float v : layer.data) sum += v;
        return std::make_pair(sum, snow.drawn());
    };
    const auto [without, n0] = draw({});
    const auto [with, n1] = draw(fields(r, wat));
    std::printf("%d particles; snow layer with the lamps' scattered light / without: %.3f\n", n0,
                with / without);
    EXPECT_EQ(n0, n1);  // the same particles
    EXPECT_GT(without, 0.0);
    EXPECT_GT(with, 1.05 * without);
}

}  // namespace deepsea
