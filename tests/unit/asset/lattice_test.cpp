#include "deepsea/asset/lattice.h"

#include <gtest/gtest.h>

#include <cmath>

#include "deepsea/core/error.h"

namespace deepsea {
namespace {

const DepthScheme kAllSchemes[] = {DepthScheme::Uniform, DepthScheme::Taylor, DepthScheme::Sqrt,
                                   DepthScheme::Log};

TEST(Lattice, CountCoversEveryPixelCentre) {
    EXPECT_EQ(lattice_count(800, 8), 101);  // 0, 8, ..., 800 (one column past 799)
    EXPECT_EQ(lattice_count(800, 1), 800);
    EXPECT_EQ(lattice_count(9, 8), 2);   // 0, 8
    EXPECT_EQ(lattice_count(10, 8), 3);  // 0, 8, 16
    EXPECT_EQ(lattice_count(1, 8), 1);
    for (int w : {1, 2, 7, 64, 641}) {
        for (int s : {1, 3, 8, 16}) {
            const int n = lattice_count(w, s);
            EXPECT_GE((n - 1) * s, w - 1) << w << " " << s;  // reaches the last pixel
            if (n > 1) {
                EXPECT_LT((n - 2) * s, w - 1) << w << " " << s;  // and no column more
            }
        }
    }
}

TEST(Lattice, MakeLattice) {
    const Camera cam{800, 600, 600, 600, 400, 300};
    const Lattice l =
        make_lattice(cam, 8, DepthScheme::Uniform, depth_samples(DepthScheme::Uniform, 4, 2.0));
    EXPECT_EQ(l.ni, 101);
    EXPECT_EQ(l.nj, 76);
    EXPECT_EQ(l.nk(), 5);
    EXPECT_EQ(l.slabs(), 4);
    EXPECT_DOUBLE_EQ(l.z_max(), 2.0);
    EXPECT_DOUBLE_EQ(l.u(3), 24.0);
    EXPECT_DOUBLE_EQ(l.v(75), 600.0);
    EXPECT_EQ(l.columns(), 101L * 76);
}

TEST(Lattice, BadInputsAreConfigErrors) {
    const Camera cam{64, 48, 50, 50, 32, 24};
    EXPECT_THROW(depth_samples(DepthScheme::Uniform, 0, 1.0), ConfigError);
    EXPECT_THROW(depth_samples(DepthScheme::Uniform, 8, 0.0), ConfigError);
    EXPECT_THROW(depth_samples(DepthScheme::Uniform, 8, -1.0), ConfigError);
    EXPECT_THROW(depth_samples(DepthScheme::Log, 8, 1.0, 0.0), ConfigError);
    EXPECT_THROW(parse_depth_scheme("exponential"), ConfigError);
    EXPECT_THROW(make_lattice(cam, 0, DepthScheme::Uniform, {0.0, 1.0}), ConfigError);
    EXPECT_THROW(make_lattice(cam, 4, DepthScheme::Uniform, {0.0}), ConfigError);
    EXPECT_THROW(make_lattice(cam, 4, DepthScheme::Uniform, {0.1, 1.0}), ConfigError);
    EXPECT_THROW(make_lattice(cam, 4, DepthScheme::Uniform, {0.0, 1.0, 1.0}), ConfigError);
}

TEST(Lattice, SchemeNamesRoundTrip) {
    for (DepthScheme s : kAllSchemes) EXPECT_EQ(parse_depth_scheme(to_string(s)), s);
}

TEST(DepthSamples, EverySchemeStartsAtZeroEndsAtZmaxAndAscends) {
    for (DepthScheme s : kAllSchemes) {
        for (int K : {1, 2, 8, 64}) {
            const auto z = depth_samples(s, K, 7.5);
            ASSERT_EQ(int(z.size()), K + 1);
            EXPECT_EQ(z.front(), 0.0);
            EXPECT_EQ(z.back(), 7.5);
            for (int k = 1; k <= K; ++k) EXPECT_GT(z[k], z[k - 1]) << to_string(s) << " K=" << K;
        }
    }
}

TEST(DepthSamples, Formulas) {
    const auto u = depth_samples(DepthScheme::Uniform, 4, 2.0);
    EXPECT_DOUBLE_EQ(u[1], 0.5);
    EXPECT_DOUBLE_EQ(u[3], 1.5);
    const auto q = depth_samples(DepthScheme::Sqrt, 4, 16.0);
    EXPECT_DOUBLE_EQ(q[1], 1.0);
    EXPECT_DOUBLE_EQ(q[2], 4.0);
    const auto g = depth_samples(DepthScheme::Log, 2, 8.0, 1.0);  // z0 ((1 + 8)^(k/2) - 1)
    EXPECT_NEAR(g[1], 2.0, 1e-12);
}

TEST(DepthSamples, TaylorSlabsAreTheTermsOfTheSeriesOfExpK) {
    // Slab n is proportional to K^n / n!: consecutive slabs grow by K / n.
    const int K = 8;
    const auto z = depth_samples(DepthScheme::Taylor, K, 10.0);
    for (int n = 1; n < K; ++n) {
        const double ratio = (z[n + 1] - z[n]) / (z[n] - z[n - 1]);
        EXPECT_NEAR(ratio, double(K) / n, 1e-9 * K) << n;
    }
    // The paper's Eq. 7 first slab, s = 2.2 z_max / e^N, is this normalisation at N = 8.
    EXPECT_NEAR(z[1] / (2.2 * 10.0 / std::exp(8.0)), 1.0, 0.01);
}

TEST(DepthPosition, BracketsEveryDepth) {
    for (DepthScheme s : kAllSchemes) {
        const Camera cam{16, 16, 10, 10, 8, 8};
        const Lattice l = make_lattice(cam, 4, s, depth_samples(s, 16, 5.0));
        for (int k = 0; k < l.slabs(); ++k) {
            const DepthPosition at = l.depth_position(l.z[k]);
            EXPECT_NEAR(l.z[at.k] + at.w * (l.z[at.k + 1] - l.z[at.k]), l.z[k], 1e-12);
            const double mid = 0.5 * (l.z[k] + l.z[k + 1]);
            const DepthPosition m = l.depth_position(mid);
            EXPECT_EQ(m.k, k) << to_string(s);
            EXPECT_NEAR(m.w, 0.5, 1e-9) << to_string(s);
        }
        EXPECT_EQ(l.depth_position(0.0).k, 0);
        EXPECT_EQ(l.depth_position(-1.0).w, 0.0);
        EXPECT_EQ(l.depth_position(5.0).k, 15);
        EXPECT_EQ(l.depth_position(5.0).w, 1.0);
        EXPECT_EQ(l.depth_position(1e9).w, 1.0);
        EXPECT_EQ(l.depth_position(INFINITY).w, 1.0);
        EXPECT_EQ(l.depth_position(NAN).k, 15);
        EXPECT_EQ(l.depth_position(NAN).w, 1.0);
    }
}

}  // namespace
TEST(LatticeCell, InteriorEdgesAndOneNode) {
    const LatticeCell<double> in = lattice_cell(2.25, 5);
    EXPECT_EQ(in.i0, 2);
    EXPECT_EQ(in.i1, 3);
    EXPECT_DOUBLE_EQ(in.w, 0.25);
    for (double x : {-1.0, 0.0, double(std::nan(""))}) {
        const LatticeCell<double> c = lattice_cell(x, 5);
        EXPECT_EQ(c.i0, 0) << x;
        EXPECT_EQ(c.w, 0.0) << x;
    }
    for (double x : {4.0, 7.5}) {  // at and beyond the last node: the last node, w = 1
        const LatticeCell<double> c = lattice_cell(x, 5);
        EXPECT_EQ(c.i0, 3);
        EXPECT_EQ(c.i1, 4);
        EXPECT_EQ(c.w, 1.0);
    }
    const LatticeCell<double> one = lattice_cell(3.0, 1);
    EXPECT_EQ(one.i0, 0);
    EXPECT_EQ(one.i1, 0);
    EXPECT_EQ(one.w, 0.0);
    // float (the runtime's tables) picks the same nodes
    const LatticeCell<float> f = lattice_cell(2.25f, 5);
    EXPECT_EQ(f.i0, 2);
    EXPECT_EQ(f.w, 0.25f);
}

TEST(Lerp, EndsAndMiddle) {
    EXPECT_EQ(lerp(2.0, 6.0, 0.0), 2.0);
    EXPECT_EQ(lerp(2.0, 6.0, 1.0), 6.0);
    EXPECT_EQ(lerp(2.0f, 6.0f, 0.25f), 3.0f);
}

}  // namespace deepsea
