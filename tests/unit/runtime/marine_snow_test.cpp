// Marine snow (runtime/marine_snow.h, optics/snow.h): the particles in view against the
// concentration times the view's volume (Poisson), a particle's light against the lamp term
// written out here, the disc against the thin lens's circle of confusion, seeds, surfaces, and
// bad values.

#include "deepsea/runtime/marine_snow.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/core/random.h"

namespace deepsea {

namespace {

Camera small_camera(double f = 150.0) {
    Camera c;
    c.width = 200;
    c.height = 150;
    c.fx = c.fy = f;
    c.cx = 99.5;
    c.cy = 74.5;
    return c;
}

Rig one_lamp() {
    Rig rig;
    Light l;
    l.position = {0.3, -0.1, 0.0};
    l.direction = normalize(Vec3{-0.2, 0.05, 1.0});
    l.intensity = {2.0, 1.5, 1.0};
    l.rid.sigma_deg = 30.0;
    rig.lights.push_back(l);
    return rig;
}

Water clear_water() {
    Water w;
    w.c = {0.2, 0.08, 0.05};
    w.b = {0.02, 0.02, 0.02};
    return w;
}

SnowSettings settings(double concentration, double max_distance = 2.0) {
    SnowSettings s;
    s.snow = snow_preset("abyssal");
    s.snow.concentration = concentration;
    s.snow.max_distance_m = max_distance;
    s.snow.phase = Phase{PhaseKind::HenyeyGreenstein, 0.3};
    return s;
}

/// Mean and variance of counts.
std::pair<double, double> moments(const std::vector<double>& n) {
    double m = 0.0, v = 0.0;
    for (double x : n) m += x;
    m /= double(n.size());
    for (double x : n) v += (x - m) * (x - m);
    return {m, v / double(n.size() - 1)};
}

/// A rotation from three angles, as a camera pose at `origin`.
CameraPose pose(const Vec3& origin, double a, double b, double c) {
    const Vec3 f =
        normalize(Vec3{std::sin(a) * std::cos(b), std::sin(b), std::cos(a) * std::cos(b)});
    const Vec3 up0 = normalize(Vec3{std::sin(c), std::cos(c), 0.1});
    const Vec3 r = normalize(cross(up0, f));
    const Vec3 d = cross(f, r);
    return {origin, r, d, f};
}

}  // namespace

TEST(MarineSnow, CountInViewIsPoissonWithConcentrationTimesVolume) {
    const Camera cam = small_camera();
    const SnowSettings s = settings(300.0);
    const double lambda = s.snow.concentration * view_volume(cam, kSnowNearM, 2.0);
    ASSERT_GT(lambda, 100.0);
    std::vector<double> fresh, posed;
    Rng rng(7);
    for (int k = 0; k < 300; ++k) {
        fresh.push_back(double(snow_particles(s, cam, std::uint64_t(k), std::nullopt).size()));
        const CameraPose p =
            pose({rng.uniform() * 50 - 25, rng.uniform() * 50 - 25, rng.uniform() * 50 - 25},
                 rng.uniform() * 6.3, rng.uniform() * 3 - 1.5, rng.uniform() * 6.3);
        posed.push_back(double(snow_particles(s, cam, 0, p).size()));
    }
    for (const auto& counts : {fresh, posed}) {
        const auto [mean, var] = moments(counts);
        // The mean of 300 Poisson counts has a standard error sqrt(lambda / 300); the sample
        // variance's relative standard error is about sqrt(2 / 299) = 0.082.
        EXPECT_NEAR(mean, lambda, 4.0 * std::sqrt(lambda / 300.0));
        EXPECT_NEAR(var / lambda, 1.0, 4.0 * 0.082);
    }
}

TEST(MarineSnow, DrawnCountIsConcentrationTimesVisibleVolume) {
    const Camera cam = small_camera();
    const SnowSettings s = settings(300.0);
    // A wall at 1.2 m over the left half, open water on the right.
    Image depth(cam.width, cam.height, 1);
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width / 2; ++u) depth.at(u, v) = 1.2f;
    const double lambda = s.snow.concentration * visible_volume(cam, depth.data, kSnowNearM, 2.0);
    MarineSnow snow(s, one_lamp(), clear_water());
    Image final(cam.width, cam.height, 3);
    std::vector<double> n;
    for (int k = 0; k < 200; ++k) {
        snow.set_frame(std::uint64_t(k), std::nullopt);
        snow.draw(cam, depth, final, nullptr, nullptr);
        n.push_back(snow.drawn());
    }
    const auto [mean, var] = moments(n);
    // Particles are kept by the pixel their centre rounds to: half a pixel of the wall's edge
    // is in doubt, far below the statistical tolerance.
    EXPECT_NEAR(mean, lambda, 4.0 * std::sqrt(lambda / 200.0) + 0.01 * lambda);
    EXPECT_NEAR(var / lambda, 1.0, 4.0 * std::sqrt(2.0 / 199.0));
}

TEST(MarineSnow, ParticleLightIsTheLampTermAtItsPosition) {
    const Camera cam = small_camera();
    SnowSettings s = settings(3.0);  // a few particles, far apart
    s.snow.albedo = 0.7;
    const Rig rig = one_lamp();
    const Water water = clear_water();
    MarineSnow snow(s, rig, water);
    Image depth(cam.width, cam.height, 1), final(cam.width, cam.height, 3),
        layer(cam.width, cam.height, 3), ids(cam.width, cam.height, 1);
    int checked = 0;
    for (std::uint64_t key = 0; key < 40 && checked < 20; ++key) {
        const auto particles = snow_particles(s, cam, key, std::nullopt);
        snow.set_frame(key, std::nullopt);
        layer = Image(cam.width, cam.height, 3);
        ids = Image(cam.width, cam.height, 1);
        snow.draw(cam, depth, final, &layer, &ids);
        const ThinLens lens{cam.fx, s.pixel_pitch_um, s.f_number, s.focus_distance_m};
        for (const SnowParticle& p : particles) {
            const Vec3& X = p.position;
            const double u = cam.fx * X.x / X.z + cam.cx, v = cam.fy * X.y / X.z + cam.cy;
            const double R = snow_disc_radius_px(cam, lens, X, p.diameter) + 1.5;
            if (u - R < 0 || v - R < 0 || u + R > cam.width - 1 || v + R > cam.height - 1) continue;
            bool alone = true;
            for (const SnowParticle& o : particles) {
                if (o.id == p.id) continue;
                const double ou = cam.fx * o.position.x / o.position.z + cam.cx;
                const double ov = cam.fy * o.position.y / o.position.z + cam.cy;
                if (std::hypot(ou - u, ov - v) < 2 * R + 2 * kMaxSnowRadiusPx) alone = false;
            }
            if (!alone) continue;
            // The lamp term, written out: I0 exp(-theta^2 / (2 sigma^2)) exp(-c d1) / d1^2,
            // scattered by albedo x HG(psi), then exp(-c d2), over the image's area in pixels.
            const Light& L = rig.lights[0];
            const Vec3 lx = X - L.position;
            const double d1 = length(lx), d2 = length(X);
            const double theta = std::acos(dot(lx, L.direction) / d1);
            const double sigma = L.rid.sigma_deg * M_PI / 180.0;
            const double cos_psi = dot(lx, X * -1.0) / (d1 * d2);
            const double g = 0.3;
            const double hg = (1 - g * g) / (4 * M_PI * std::pow(1 + g * g - 2 * g * cos_psi, 1.5));
            const double area =
                M_PI * p.diameter * p.diameter / 4.0 * cam.fx * cam.fy * d2 / (X.z * X.z * X.z);
            const double I0[3] = {L.intensity.r, L.intensity.g, L.intensity.b};
            const double c[3] = {water.c.r, water.c.g, water.c.b};
            for (int ch = 0; ch < 3; ++ch) {
                const double expected = I0[ch] * std::exp(-theta * theta / (2 * sigma * sigma)) *
                                        std::exp(-c[ch] * d1) / (d1 * d1) * 0.7 * hg *
                                        std::exp(-c[ch] * d2) * area;
                double sum = 0.0;
                for (int y = int(v - R); y <= int(v + R) + 1; ++y)
                    for (int x = int(u - R); x <= int(u + R) + 1; ++x) sum += layer.at(x, y, ch);
                EXPECT_NEAR(sum, expected, 1e-4 * expected) << "particle " << p.id;
            }
            EXPECT_EQ(ids.at(int(std::lround(u)), int(std::lround(v))), float(p.id));
            ++checked;
        }
    }
    EXPECT_GE(checked, 5);
}

TEST(MarineSnow, DiscIsTheThinLensCircleOfConfusion) {
    const Camera cam = small_camera(600.0);
    // f = 600 px x 20 um = 12 mm at f/1: a 12 mm aperture, focused at 2 m.
    const ThinLens lens{cam.fx, 20.0, 1.0, 2.0};
    const double f = 0.012, A = f / 1.0, s = 2.0;
    for (const double z : {0.3, 0.5, 1.0, 2.0, 3.0}) {
        // From the lens equation: a point at z images at z' = f z / (z - f), the sensor sits
        // at s' = f s / (s - f); the cone of the aperture A is A |z' - s'| / z' wide there.
        const double zi = f * z / (z - f), si = f * s / (s - f);
        const double blur_px = A * std::fabs(zi - si) / zi / 20e-6;
        EXPECT_NEAR(circle_of_confusion_px(lens, z), blur_px, 1e-9 * (1 + blur_px)) << z;
        const Vec3 X{0.0, 0.0, z};
        const double D = 0.5e-3;
        const double r_geo = cam.fx * D / 2 / z;  // on the axis
        const double R = std::clamp(r_geo + blur_px / 2, 0.5, kMaxSnowRadiusPx);
        EXPECT_NEAR(snow_disc_radius_px(cam, lens, X, D), R, 1e-9 * R) << z;
    }
    // Drawn: the pixels a lone particle lights fill a disc of that radius.
    SnowSettings st = settings(30.0, 1.0);
    st.f_number = 1.0;
    st.pixel_pitch_um = 20.0;
    st.focus_distance_m = 2.0;
    MarineSnow snow(st, one_lamp(), clear_water());
    Image depth(cam.width, cam.height, 1);
    int checked = 0;
    for (std::uint64_t key = 0; key < 200 && checked < 5; ++key) {
        const auto particles = snow_particles(st, cam, key, std::nullopt);
        if (particles.size() != 1) continue;
        const Vec3& X = particles[0].position;
        const double u = cam.fx * X.x / X.z + cam.cx, v = cam.fy * X.y / X.z + cam.cy;
        const double R = snow_disc_radius_px(cam, lens, X, particles[0].diameter);
        if (R < 2.0 || u - R < 1 || v - R < 1 || u + R > cam.width - 2 || v + R > cam.height - 2)
            continue;
        Image final(cam.width, cam.height, 3);
        snow.set_frame(key, std::nullopt);
        snow.draw(cam, depth, final, nullptr, nullptr);
        double lit = 0.0;  // coverage falls from 1 to 0 over the last pixel: area pi R^2 + ...
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x)
                lit += final.at(x, y, 1) / final.at(int(u), int(v), 1);
        // Sum of coverage over the disc / the centre's (1): pi R^2 within a pixel of edge.
        EXPECT_NEAR(lit, M_PI * R * R, 2.0 * M_PI * R * 0.5) << "R = " << R;
        ++checked;
    }
    EXPECT_GE(checked, 1);
}

TEST(MarineSnow, SeedsAndSurfaces) {
    const Camera cam = small_camera();
    const SnowSettings s = settings(200.0);
    const auto a = snow_particles(s, cam, 5, std::nullopt);
    const auto b = snow_particles(s, cam, 5, std::nullopt);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].position.x, b[i].position.x);
    SnowSettings other = s;
    other.seed = 2;
    const auto c = snow_particles(other, cam, 5, std::nullopt);
    const auto d = snow_particles(s, cam, 6, std::nullopt);  // another frame: afresh
    std::map<double, int> xs;
    for (const auto& p : a) xs[p.position.x] = 1;
    int shared = 0;
    for (const auto& p : c) shared += xs.count(p.position.x);
    for (const auto& p : d) shared += xs.count(p.position.x);
    EXPECT_EQ(shared, 0);

    // With a pose, the particles are the world's: a camera moved 10 cm sees the same points.
    const CameraPose p0 = pose({1, 2, 3}, 0.2, 0.1, 0.3);
    CameraPose p1 = p0;
    p1.origin = p0.origin + p0.forward * 0.1;
    const auto w0 = snow_particles(s, cam, 1, p0), w1 = snow_particles(s, cam, 2, p1);
    // Every particle p1 sees that p0 also sees (0.1 m farther, nearer the axis) is in both.
    const auto key = [](const Vec3& x) {
        return std::tuple{std::llround(x.x * 1e6), std::llround(x.y * 1e6),
                          std::llround(x.z * 1e6)};
    };
    std::map<std::tuple<long long, long long, long long>, int> seen;
    for (const auto& p : w0) seen[key(p.position)] = 1;
    int expected = 0, found = 0;
    for (const auto& p : w1) {
        if (p.position.z + 0.1 > s.snow.max_distance_m - 1e-6) continue;
        ++expected;
        found += int(seen.count(key(p.position + Vec3{0, 0, 0.1})));
    }
    EXPECT_GT(expected, 100);
    EXPECT_EQ(found, expected);

    // Same seed, same image; a wall at 0.6 m hides every particle behind it.
    Image wall(cam.width, cam.height, 1, 0.6f);
    MarineSnow snow(s, one_lamp(), clear_water());
    Image f1(cam.width, cam.height, 3), f2(cam.width, cam.height, 3);
    Image layer(cam.width, cam.height, 3), ids(cam.width, cam.height, 1);
    snow.set_frame(5, std::nullopt);
    snow.draw(cam, wall, f1, &layer, &ids);
    snow.draw(cam, wall, f2, nullptr, nullptr);
    EXPECT_EQ(f1.data, f2.data);
    int nearer = 0;
    for (const auto& p : a) nearer += p.position.z < 0.6;
    EXPECT_EQ(snow.drawn(), nearer);
    EXPECT_GT(nearer, 0);
    for (float id : ids.data) {
        if (id == 0.0f) continue;
        EXPECT_LT(a[std::size_t(id) - 1].position.z, 0.6);
    }
}

TEST(MarineSnow, BadValuesNameTheirKey) {
    const auto message = [](auto&& f) -> std::string {
        try {
            f();
        } catch (const ConfigError& e) {
            return e.what();
        }
        return "";
    };
    const std::string unknown = message([] { snow_preset("blizzard"); });
    EXPECT_NE(unknown.find("--snow"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("blizzard"), std::string::npos) << unknown;
    SnowSettings s = settings(-5.0);
    const std::string negative = message([&] { validate(s); });
    EXPECT_EQ(negative.rfind("snow.concentration:", 0), 0u) << negative;
    s = settings(10.0);
    s.focus_distance_m = 0.0;
    const std::string focus = message([&] { validate(s); });
    EXPECT_EQ(focus.rfind("camera.lens.focus_distance_m:", 0), 0u) << focus;
    for (const std::string& m : {unknown, negative, focus})
        EXPECT_EQ(m.find('\n'), std::string::npos);
}

}  // namespace deepsea
