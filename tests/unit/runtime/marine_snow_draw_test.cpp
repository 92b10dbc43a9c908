// Marine snow's float rows and drawing (runtime/snow_light.h, marine_snow_draw.cpp): the rows
// against optics' particle_radiance in double for every kind of lamp profile and phase
// function, a sub-pixel particle's bilinear weights, the same image at any thread count, and
// the same image from the cells kept across a flight as from a fresh start, and `final` drawn
// alone (the bands' compact entries) the same as with the other layers.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/core/random.h"
#include "deepsea/optics/transmission.h"
#include "deepsea/runtime/marine_snow.h"
#include "deepsea/runtime/snow_light.h"
#include "snow_fixtures.h"

namespace deepsea {

// The placing's sizes in rows (snow_diameters, libmvec's pow) against SnowSizes' scalar pow:
// each preset, the slopes 0, 1 (the logarithmic form), 2.5 and 6, quantiles at both ends.
TEST(SnowSizes, RowsMatchScalar) {
    Rng rng(5);
    std::vector<Snow> snows;
    for (const std::string& name : snow_preset_names()) snows.push_back(snow_preset(name));
    for (const double slope : {0.0, 1.0, 2.5, 6.0}) {
        Snow s = snow_preset("abyssal");
        s.slope = slope;
        snows.push_back(s);
    }
    for (const Snow& snow : snows) {
        const SnowSizes sizes(snow);
        std::vector<double> q(1001);  // not a multiple of any vector width
        for (double& v : q) v = rng.uniform();
        q[0] = 0.0;
        q[1] = 1.0 - 0x1.0p-53;
        std::vector<double> d = q;
        snow_diameters(sizes, d.data(), int(d.size()));
        double worst = 0.0;
        for (std::size_t i = 0; i < q.size(); ++i) {
            const double exact = sizes(q[i]);
            worst = std::max(worst, std::fabs(d[i] - exact) / exact);
        }
        // The presets' slopes (3-3.5) to 1e-14; the steepest, 6, loses more to the rounding of
        // a^k + q (b^k - a^k) near q = 1 (its terms cancel; the vector loop may fuse them).
        EXPECT_LT(worst, snow.slope <= 4.0 ? 1e-14 : 1e-12) << snow.name << " slope " << snow.slope;
        std::printf("snow_diameters, %s slope %.1f: largest relative difference %.2g\n",
                    snow.name.c_str(), snow.slope, worst);
    }
}

TEST(MarineSnowDraw, FloatLightMatchesParticleRadiance) {
    const Camera cam = testing::snow_camera();
    const Water wat = testing::snow_water();
    Rng rng(11);
    const int n = 301;  // not a multiple of any vector width
    const testing::ParticleSet ps = testing::random_particles(rng, n, 3.0);
    const std::vector<Vec3>& X = ps.X;
    const std::vector<float>& D = ps.D;
    for (const bool table : {false, true})
        for (const Phase phase :
             {Phase{PhaseKind::Isotropic, 0.0}, Phase{PhaseKind::HenyeyGreenstein, 0.6},
              Phase{PhaseKind::PetzoldClear, 0.0}}) {
            const Rig rig = testing::snow_lamps(table);
            Snow snow = snow_preset("nepheloid");
            snow.albedo = 0.4;
            snow.phase = phase;
            std::vector<float> e(3 * std::size_t(n)), scratch(5 * std::size_t(n));
            float* s = scratch.data();
            snow_light(rig, wat, snow, cam.fx, cam.fy, ps.rows(), e.data(), e.data() + n,
                       e.data() + 2 * n,
                       SnowLightScratch{s, s + n, s + 2 * n, s + 3 * n, s + 4 * n});
            int lit = 0;
            for (int q = 0; q < n; ++q) {
                // Written from optics' double functions: radiance, water, area in pixels.
                const Vec3& p = X[std::size_t(q)];
                const double d2 = length(p), Dq = double(D[std::size_t(q)]);
                const double area = M_PI / 4 * Dq * Dq * cam.fx * cam.fy * d2 / std::pow(p.z, 3);
                const Rgb L = particle_radiance(rig, wat, snow, p) * transmission(wat.c, d2) * area;
                const double want[3] = {L.r, L.g, L.b};
                const double scale = std::max({want[0], want[1], want[2]});
                lit += scale > 0.0;
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(e[std::size_t(c * n + q)], want[c], 2e-4 * scale + 1e-30)
                        << "table " << table << " phase " << int(phase.kind) << " particle " << q;
            }
            EXPECT_GT(lit, n / 2);
        }
}

TEST(MarineSnowDraw, SubPixelParticleIsSharedBilinearly) {
    const Camera cam = testing::snow_camera();
    SnowSettings s;
    s.snow = snow_preset("abyssal");
    s.snow.concentration = 0.3;  // about 7 particles in view
    MarineSnow snow(s, testing::snow_lamps(false), testing::snow_water());
    const ThinLens lens{cam.fx, s.pixel_pitch_um, s.f_number, s.focus_distance_m};
    const Image depth(cam.width, cam.height, 1);
    int checked = 0;
    for (std::uint64_t key = 0; key < 400 && checked < 10; ++key) {
        const auto particles = snow_particles(s, cam, key, std::nullopt);
        Image final(cam.width, cam.height, 3);
        snow.set_frame(key, std::nullopt);
        snow.draw(cam, depth, final, nullptr, nullptr);
        for (const SnowParticle& p : particles) {
            const Vec3& X = p.position;
            if (snow_disc_radius_px(cam, lens, X, p.diameter) > 0.5) continue;
            const double u = cam.fx * X.x / X.z + cam.cx, v = cam.fy * X.y / X.z + cam.cy;
            const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
            if (x0 < 0 || y0 < 0 || x0 + 1 >= cam.width || y0 + 1 >= cam.height) continue;
            bool alone = true;  // no other particle within 40 px
            for (const SnowParticle& o : particles) {
                const double ou = cam.fx * o.position.x / o.position.z + cam.cx;
                const double ov = cam.fy * o.position.y / o.position.z + cam.cy;
                alone &= o.id == p.id || std::hypot(ou - u, ov - v) > 2 * kMaxSnowRadiusPx + 4;
            }
            if (!alone) continue;
            const double fu = u - x0, fv = v - y0;
            const double sum = final.at(x0, y0, 1) + final.at(x0 + 1, y0, 1) +
                               final.at(x0, y0 + 1, 1) + final.at(x0 + 1, y0 + 1, 1);
            if (!(sum > 0.0)) continue;
            EXPECT_NEAR(final.at(x0, y0, 1) / sum, (1 - fu) * (1 - fv), 1e-4);
            EXPECT_NEAR(final.at(x0 + 1, y0, 1) / sum, fu * (1 - fv), 1e-4);
            EXPECT_NEAR(final.at(x0, y0 + 1, 1) / sum, (1 - fu) * fv, 1e-4);
            EXPECT_NEAR(final.at(x0 + 1, y0 + 1, 1) / sum, fu * fv, 1e-4);
            EXPECT_EQ(final.at(x0 - 1, y0, 1), 0.0f);
            EXPECT_EQ(final.at(x0 + 2, y0 + 1, 1), 0.0f);
            ++checked;
        }
    }
    EXPECT_GE(checked, 5);
}

TEST(MarineSnowDraw, SameImageAtAnyThreadCount) {
    const Camera cam = testing::snow_camera();
    SnowSettings s;
    s.snow = snow_preset("plume");
    s.focus_distance_m = 1.5;
    s.f_number = 1.4;  // large soft discs near the lens, overlapping across bands
    MarineSnow snow(s, testing::snow_lamps(true), testing::snow_water());
    const Image depth = testing::slanted_floor(cam, 3.0);
    const auto draw = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        std::vector<Image> out{Image(cam.width, cam.height, 3), Image(cam.width, cam.height, 3),
                               Image(cam.width, cam.height, 1)};
        snow.set_frame(3, std::nullopt);
        snow.draw(cam, depth, out[0], &out[1], &out[2]);
        return out;
    };
    const auto one = draw(1), many = draw(8);
    ASSERT_GT(snow.drawn(), 1000);
    for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one[i].data, many[i].data) << i;
    double sum = 0.0;
    for (float f : one[1].data) sum += f;
    EXPECT_GT(sum, 0.0);
}

// With a pose the placing keeps each cell's particles while the view meets it: along a flight
// (moving, turning, jumping away and back, a frame without a pose between) every frame's
// image, snow layer and ids are those of a MarineSnow made for that frame alone.
TEST(MarineSnowDraw, KeptCellsGiveAFreshStartsImage) {
    const Camera cam = testing::snow_camera();
    SnowSettings s;
    s.snow = snow_preset("plume");
    const Rig rig = testing::snow_lamps(false);
    MarineSnow kept(s, rig, testing::snow_water());
    const Image depth = testing::slanted_floor(cam, 3.0);
    const auto draw = [&](const MarineSnow& snow) {
        std::vector<Image> out{Image(cam.width, cam.height, 3), Image(cam.width, cam.height, 3),
                               Image(cam.width, cam.height, 1)};
        snow.draw(cam, depth, out[0], &out[1], &out[2]);
        return out;
    };
    const auto pose = [](double x, double yaw) {
        CameraPose p;
        p.origin = {x, 0.3 * x, -0.2 * x};
        p.right = {std::cos(yaw), 0.0, -std::sin(yaw)};
        p.forward = {std::sin(yaw), 0.0, std::cos(yaw)};
        return p;
    };
    const std::vector<std::optional<CameraPose>> flight{
        pose(0.0, 0.0),  pose(0.1, 0.0),  pose(0.25, 0.05), pose(0.4, 0.3), std::nullopt,
        pose(0.45, 0.3), pose(40.0, 1.0), pose(0.5, 0.3),   pose(0.5, 0.3)};
    for (std::size_t f = 0; f < flight.size(); ++f) {
        kept.set_frame(f, flight[f]);
        MarineSnow fresh(s, rig, testing::snow_water());
        fresh.set_frame(f, flight[f]);
        const auto a = draw(kept), b = draw(fresh);
        EXPECT_GT(kept.drawn(), 100) << f;
        EXPECT_EQ(kept.drawn(), fresh.drawn()) << f;
        for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].data, b[i].data) << f << " " << i;
    }
}

// Drawn alone, `final` takes the sub-pixel particles from the bands' compact entries and the
// discs from their records, in the same order as with the snow layer and ids: the same bits,
// with large soft discs among the splats and across the bands' edges.
TEST(MarineSnowDraw, FinalAloneIsTheFinalDrawnWithTheLayers) {
    const Camera cam = testing::snow_camera();
    SnowSettings s;
    s.snow = snow_preset("plume");
    s.focus_distance_m = 1.5;
    s.f_number = 1.4;
    MarineSnow snow(s, testing::snow_lamps(true), testing::snow_water());
    const Image depth = testing::slanted_floor(cam, 3.0);
    for (std::uint64_t key = 0; key < 3; ++key) {
        snow.set_frame(key, std::nullopt);
        Image alone(cam.width, cam.height, 3), with(cam.width, cam.height, 3),
            layer(cam.width, cam.height, 3), ids(cam.width, cam.height, 1);
        snow.draw(cam, depth, alone, nullptr, nullptr);
        const int drawn = snow.drawn();
        snow.draw(cam, depth, with, &layer, &ids);
        EXPECT_GT(drawn, 1000);
        EXPECT_EQ(drawn, snow.drawn());
        EXPECT_EQ(alone.data, with.data) << key;
    }
}

}  // namespace deepsea
