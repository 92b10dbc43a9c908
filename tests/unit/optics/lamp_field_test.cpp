#include "deepsea/optics/lamp_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "deepsea/core/random.h"
#include "deepsea/optics/multiple_scattering.h"

namespace deepsea {

namespace {

Water hg_water() {
    Water w;
    w.c = Rgb(0.9, 0.6, 0.7);
    w.b = Rgb(0.5, 0.45, 0.5);
    w.phase = Phase{PhaseKind::HenyeyGreenstein, 0.9};
    return w;
}

/// The lamp's table on nr x ntheta nodes from r0 to r_max metres, `samples` directions a node.
LampField table(const Light& lamp, const Water& w, int nr, int ntheta, double r0, double r_max,
                int samples) {
    LampFieldSettings s;
    s.nr = nr;
    s.ntheta = ntheta;
    s.r0 = r0;
    s.r_max = r_max;
    s.samples = samples;
    return bake_lamp_field(lamp, w, s);
}

}  // namespace

TEST(LampField, TableGivesTheScatteredIrradianceOfARotatedLampAnywhere) {
    // A lamp somewhere, tilted; a point off the table's nodes at some azimuth; tilted normals.
    // The table (lamp frame) must give what a direct estimate in the camera frame gives.
    Light lamp;
    lamp.position = Vec3(-0.4, 0.1, 0.05);
    lamp.direction = normalize(Vec3(0.5, -0.1, 0.85));
    lamp.intensity = Rgb(1.0, 0.8, 0.6);
    lamp.rid.sigma_deg = 30.0;
    const Water w = hg_water();
    const LampField f = table(lamp, w, 24, 25, 0.05, 10.0, 2048);
    EXPECT_GT(f.rel_std_error, 0.0);
    EXPECT_LT(f.rel_std_error, 0.1);

    Vec3 ex, ey;
    lamp_frame(lamp.direction, ex, ey);
    const Transport tr(Rig{"one", {lamp}}, w);
    const Vec3 P(0.6, -0.3, 2.2);
    Rng rng(4);
    for (const Vec3 n : {normalize(Vec3(0, 0, -1)), normalize(Vec3(-0.6, 0.2, -0.7)),
                         normalize(lamp.position - P)}) {
        const Vec3 p = P - lamp.position;
        double e[3];
        lamp_field_irradiance(LampFieldView<double>(f), dot(p, ex), dot(p, ey),
                              dot(p, lamp.direction), dot(n, ex), dot(n, ey),
                              dot(n, lamp.direction), e[0], e[1], e[2]);
        float ef[3];
        lamp_field_irradiance(LampFieldView<float>(f), float(dot(p, ex)), float(dot(p, ey)),
                              float(dot(p, lamp.direction)), float(dot(n, ex)), float(dot(n, ey)),
                              float(dot(n, lamp.direction)), ef[0], ef[1], ef[2]);
        double sum[3] = {}, sum2 = 0.0;
        const int samples = 100000;
        for (int i = 0; i < samples; ++i) {
            const PhaseSample ps = tr.any_direction(P, rng);
            const double c = dot(n, ps.direction);
            if (c <= 0.0) continue;
            const Rgb L = tr.scattered_radiance(P, ps.direction, rng) * (ps.weight * c);
            for (int k = 0; k < 3; ++k) sum[k] += L[k] / samples;
            sum2 += L.g * L.g / samples;
        }
        const double se = std::sqrt((sum2 - sum[1] * sum[1]) / samples);
        for (int k = 0; k < 3; ++k) {
            const double expect = sum[k] / lamp.intensity[k];  // the table is per unit intensity
            // interpolation + order-2 truncation + both estimates' noise
            EXPECT_NEAR(e[k], expect, 0.08 * expect + 4.0 * se) << "channel " << k;
            EXPECT_NEAR(ef[k], e[k], 1e-4 * e[k] + 1e-9);
        }
    }
}

TEST(LampField, SymmetricTableGivesMirrorImagesTheSameLight) {
    // A lamp's light is mirror-symmetric about any plane through its axis: at (x, y, z) with
    // normal (nx, ny, nz) as at (x, -y, z) with (nx, -ny, nz). The estimated table is that
    // only up to its noise; with `symmetric` exactly, and its even coefficients are unchanged.
    Light lamp;
    lamp.rid.sigma_deg = 20.0;
    LampFieldSettings s;
    s.nr = 6;
    s.ntheta = 7;
    s.r0 = 0.1;
    s.r_max = 4.0;
    s.samples = 256;
    const LampField noisy = bake_lamp_field(lamp, hg_water(), s);
    s.symmetric = true;
    const LampField sym = bake_lamp_field(lamp, hg_water(), s);
    const auto mirror_gap = [](const LampField& f) {
        double gap = 0.0;
        for (const Vec3 n : {normalize(Vec3(0.3, 0.5, -0.8)), normalize(Vec3(-0.7, -0.4, 0.2))}) {
            double a[3], b[3];
            lamp_field_irradiance(LampFieldView<double>(f), 0.5, 0.7, 1.2, n.x, n.y, n.z, a[0],
                                  a[1], a[2]);
            lamp_field_irradiance(LampFieldView<double>(f), 0.5, -0.7, 1.2, n.x, -n.y, n.z, b[0],
                                  b[1], b[2]);
            for (int c = 0; c < 3; ++c) gap = std::max(gap, std::abs(a[c] - b[c]) / (a[c] + b[c]));
        }
        return gap;
    };
    EXPECT_GT(mirror_gap(noisy), 1e-4);  // can fail: the noise that `symmetric` removes
    EXPECT_LT(mirror_gap(sym), 1e-6);
    for (std::size_t n = 0; n < sym.sh.size(); ++n) {
        const int m = int(n / 3 % kShCount);
        if (m == 1 || m == 4 || m == 5)
            EXPECT_EQ(sym.sh[n], 0.0f);
        else
            EXPECT_EQ(sym.sh[n], noisy.sh[n]);
    }
}

TEST(LampField, NoScatteredLightBeyondTheTable) {
    Light lamp;
    const LampField f = table(lamp, hg_water(), 4, 5, 0.1, 2.0, 16);
    double e[3];
    lamp_field_irradiance(LampFieldView<double>(f), 0.0, 0.0, 2.5, 0.0, 0.0, -1.0, e[0], e[1],
                          e[2]);
    EXPECT_EQ(e[0] + e[1] + e[2], 0.0);
    lamp_field_irradiance(LampFieldView<double>(f), 0.0, 0.0, 1.5, 0.0, 0.0, -1.0, e[0], e[1],
                          e[2]);
    EXPECT_GT(e[1], 0.0);
}

}  // namespace deepsea

namespace deepsea {

TEST(LampField, QuadraticFormInAnyFrameIsTheSameIrradiance) {
    // The form written in the camera frame (axes of a tilted lamp given in camera coordinates)
    // and evaluated at a camera-frame normal equals the lamp-frame evaluation at the same
    // normal expressed in the lamp frame: the rotation of b and Q is right.
    Light lamp;
    lamp.direction = normalize(Vec3(0.4, -0.3, 0.85));
    const LampField f = table(lamp, hg_water(), 8, 9, 0.1, 8.0, 64);
    Vec3 ex, ey;
    lamp_frame(lamp.direction, ex, ey);
    const Vec3& a = lamp.direction;
    Rng rng(11);
    for (int t = 0; t < 50; ++t) {
        const Vec3 p =
            rotate_about(Vec3(0, 0, 1), 1.0 - 2.0 * rng.uniform(), 2.0 * M_PI * rng.uniform()) *
            (0.2 + 5.0 * rng.uniform());
        const Vec3 n =
            rotate_about(Vec3(0, 0, 1), 1.0 - 2.0 * rng.uniform(), 2.0 * M_PI * rng.uniform());
        const double lp[3] = {dot(p, ex), dot(p, ey), dot(p, a)};
        double qc[3 * kQuadraticCount], ql[3 * kQuadraticCount];
        lamp_field_quadratic(LampFieldView<double>(f), ex.x, ex.y, ex.z, ey.x, ey.y, ey.z, a.x, a.y,
                             a.z, lp[0], lp[1], lp[2], qc, 1);
        lamp_field_quadratic(LampFieldView<double>(f), 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0,
                             lp[0], lp[1], lp[2], ql, 1);
        for (int c = 0; c < 3; ++c) {
            const double cam = quadratic_irradiance(qc + c * kQuadraticCount, 1, n.x, n.y, n.z);
            const double loc = quadratic_irradiance(ql + c * kQuadraticCount, 1, dot(n, ex),
                                                    dot(n, ey), dot(n, a));
            EXPECT_NEAR(cam, loc, 1e-9 * (std::fabs(loc) + 1e-12));
        }
    }
}

}  // namespace deepsea
