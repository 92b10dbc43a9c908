// A particle's in-scatter of the lamps' scattered light (optics/lamp_field.h,
// quadratic_in_scatter; optics/phase.h, Phase::legendre_moment): the Funk-Hecke shortcut
// against direct integration of the stored radiance times the phase function over the sphere.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "deepsea/core/random.h"
#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/phase.h"
#include "deepsea/optics/spherical_harmonics.h"

namespace deepsea {

namespace {

/// integral over the sphere of L(d) p(d . v) dd, in a frame about v: psi on a grid fine near 0
/// (Petzold's forward peak), phi with 64 points (exact for L's order-2 dependence on phi).
double direct(const Phase& phase, const double* L, const Vec3& er, const Vec3& ephi, const Vec3& a,
              const Vec3& v) {
    Vec3 e1 = normalize(std::fabs(v.x) < 0.9 ? cross(v, Vec3{1, 0, 0}) : cross(v, Vec3{0, 1, 0}));
    const Vec3 e2 = cross(v, e1);
    std::vector<double> psi;
    for (int i = 0; i < 400; ++i) psi.push_back(1e-6 * std::pow(0.1 / 1e-6, i / 400.0));
    for (int i = 0; i <= 4000; ++i) psi.push_back(0.1 + (M_PI - 0.1) * i / 4000.0);
    const auto ring = [&](double s) {  // integral over phi of L at angle s from v, times p
        double sum = 0;
        for (int k = 0; k < 64; ++k) {
            const double phi = 2 * M_PI * (k + 0.5) / 64;
            const Vec3 d =
                v * std::cos(s) + (e1 * std::cos(phi) + e2 * std::sin(phi)) * std::sin(s);
            double Y[kShCount];
            sh_basis(dot(d, er), dot(d, ephi), dot(d, a), Y);
            double l = 0;
            for (int m = 0; m < kShCount; ++m) l += L[m] * Y[m];
            sum += l;
        }
        return sum * (2 * M_PI / 64) * phase(std::cos(s)) * std::sin(s);
    };
    double total = ring(psi[0]) * psi[0] / 2, prev = ring(psi[0]);
    for (std::size_t i = 1; i < psi.size(); ++i) {
        const double cur = ring(psi[i]);
        total += 0.5 * (prev + cur) * (psi[i] - psi[i - 1]);
        prev = cur;
    }
    return total;
}

}  // namespace

TEST(ParticleInScatter, LegendreMomentsOfHenyeyGreensteinAreItsPowers) {
    for (double g : {-0.3, 0.0, 0.5, 0.9}) {
        const Phase p{PhaseKind::HenyeyGreenstein, g};
        EXPECT_DOUBLE_EQ(p.legendre_moment(0), 1.0);
        EXPECT_DOUBLE_EQ(p.legendre_moment(1), g);
        EXPECT_DOUBLE_EQ(p.legendre_moment(2), g * g);
    }
    EXPECT_EQ(Phase{}.legendre_moment(1), 0.0);
    EXPECT_THROW(Phase{}.legendre_moment(3), std::invalid_argument);
    // Petzold: strongly forward, so both moments lie near 1 but below it, k2 < k1.
    for (PhaseKind k : {PhaseKind::PetzoldClear, PhaseKind::PetzoldTurbid}) {
        const Phase p{k, 0.0};
        EXPECT_GT(p.legendre_moment(1), 0.8);
        EXPECT_LT(p.legendre_moment(2), p.legendre_moment(1));
        EXPECT_GT(p.legendre_moment(2), 0.5);
    }
}

TEST(ParticleInScatter, FunkHeckeShortcutMatchesIntegrationOverTheSphere) {
    // One field with the same random order-2 radiance at every node; a point off the node
    // half-plane (so the table's radial/azimuthal axes are rotated), several views and phases.
    Rng rng(5);
    LampField f;
    f.nr = f.ntheta = 2;
    f.r0 = 0.01;
    f.r_max = 10.0;
    double L[3][kShCount];
    for (int c = 0; c < 3; ++c)
        for (int m = 0; m < kShCount; ++m) L[c][m] = m == 0 ? 2.0 + c : 0.6 * (rng.uniform() - 0.5);
    for (int node = 0; node < 4; ++node)
        for (int m = 0; m < kShCount; ++m)
            for (int c = 0; c < 3; ++c) f.sh.push_back(float(L[c][m]));
    const LampFieldView<double> view(f);
    const double px = 0.3, py = 0.4, pz = 1.2, rho = std::hypot(px, py);
    const Vec3 er{px / rho, py / rho, 0}, ephi{-py / rho, px / rho, 0}, a{0, 0, 1};
    double q[3 * kQuadraticCount];
    lamp_field_quadratic(view, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, px, py, pz, q, 1);
    for (const Phase phase :
         {Phase{PhaseKind::Isotropic, 0.0}, Phase{PhaseKind::HenyeyGreenstein, 0.7},
          Phase{PhaseKind::HenyeyGreenstein, -0.4}, Phase{PhaseKind::PetzoldCoastal, 0.0}}) {
        const double k1 = phase.legendre_moment(1), k2 = phase.legendre_moment(2);
        for (const Vec3 v :
             {Vec3{0, 0, 1}, normalize(Vec3{0.5, -0.3, 0.8}), normalize(Vec3{-0.7, 0.6, -0.2})}) {
            for (int c = 0; c < 3; ++c) {
                const double got =
                    quadratic_in_scatter(q + c * kQuadraticCount, 1, k1, k2, v.x, v.y, v.z);
                const double want = direct(phase, L[c], er, ephi, a, v);
                EXPECT_NEAR(got, want, 2e-4 * want)
                    << "phase " << int(phase.kind) << " channel " << c << " v " << v.x << "," << v.y
                    << "," << v.z;
            }
        }
    }
    // Isotropic scattering of any radiance is its mean over the sphere: L_00 Y_00.
    EXPECT_NEAR(quadratic_in_scatter(q, 1, 0.0, 0.0, 0.0, 0.0, 1.0), L[0][0] * 0.282094791773878,
                1e-12 * L[0][0]);
}

}  // namespace deepsea
