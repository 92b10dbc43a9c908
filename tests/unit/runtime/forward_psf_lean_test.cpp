// The forward scatter's lean on surfaces tilted to the ray (optics/forward_lean.h, the blur's
// lean in forward_psf_blur.h): the lean is minus half the gradient of ln(range), checked against
// ranges to planes computed here; the blur with a lean moves light (its centroid by the lean
// times the kernel's second moment, from the optics' own weights) without making or losing
// any, and leaves a uniform surface uniform.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deepsea/optics/forward_lean.h"
#include "deepsea/optics/forward_transport.h"
#include "deepsea/runtime/forward_psf_blur.h"
#include "runtime_fixtures.h"

namespace deepsea {
namespace {

/// ln(range) along the pixel ray (x, y, 1) to the plane n . X = 1.
double log_range(double x, double y, const double n[3]) {
    const double t = 1.0 / (n[0] * x + n[1] * y + n[2]);  // planar depth
    return std::log(t * std::sqrt(x * x + y * y + 1.0));
}

TEST(ForwardLean, IsMinusHalfTheGradientOfLogRange) {
    const double fx = 600.0, fy = 550.0;
    // planes facing the camera, tilted either way, seen on and off axis
    const double planes[][3] = {{0.0, 0.0, 0.5}, {0.2, -0.1, 0.4}, {-0.3, 0.05, 0.6}};
    for (const auto& n : planes) {
        for (const double x : {0.0, 0.3, -0.55}) {
            for (const double y : {0.0, -0.2, 0.45}) {
                float lu = 0.0f, lv = 0.0f;
                forward_lean(float(x), float(y), float(n[0]), float(n[1]), float(n[2]), float(fx),
                             float(fy), lu, lv);
                const double h = 1e-4;  // in x, y: 0.06 px
                const double gu = (log_range(x + h, y, n) - log_range(x - h, y, n)) / (2 * h * fx);
                const double gv = (log_range(x, y + h, n) - log_range(x, y - h, n)) / (2 * h * fy);
                EXPECT_NEAR(lu, -0.5 * gu, 1e-5 * (1.0 + std::abs(fx * gu)) / fx) << x << " " << y;
                EXPECT_NEAR(lv, -0.5 * gv, 1e-5 * (1.0 + std::abs(fy * gv)) / fy) << x << " " << y;
            }
        }
    }
    // a surface square to the ray has none; a plane facing the camera leans towards the image
    // centre off axis (its range grows outwards); either sign of normal; no surface, none
    float lu = 1.0f, lv = 1.0f;
    forward_lean(0.4f, -0.3f, -0.4f, 0.3f, -1.0f, 500.0f, 500.0f, lu, lv);
    EXPECT_NEAR(lu, 0.0f, 1e-9f);
    EXPECT_NEAR(lv, 0.0f, 1e-9f);
    forward_lean(0.4f, -0.3f, 0.0f, 0.0f, 1.0f, 500.0f, 500.0f, lu, lv);
    EXPECT_LT(lu, 0.0f);
    EXPECT_GT(lv, 0.0f);
    float mu = 0.0f, mv = 0.0f;
    forward_lean(0.4f, -0.3f, 0.0f, 0.0f, -2.0f, 500.0f, 500.0f, mu, mv);
    EXPECT_FLOAT_EQ(mu, lu);
    EXPECT_FLOAT_EQ(mv, lv);
    forward_lean(0.4f, -0.3f, 0.0f, 0.0f, 0.0f, 500.0f, 500.0f, lu, lv);
    EXPECT_EQ(lu, 0.0f);
    EXPECT_EQ(lv, 0.0f);
    // edge-on: held at tan(alpha) = kForwardLeanMaxTilt, finite
    forward_lean(0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 500.0f, 500.0f, lu, lv);
    EXPECT_NEAR(std::hypot(lu, lv), (kForwardLeanRho - 1.0f) * kForwardLeanMaxTilt / 500.0f, 1e-7);
}

Image blurred(ForwardPsfBlur& blur, const Image& surface, const Image& d2, const Image* lean) {
    blur.prepare(surface, d2, nullptr, -1.0, lean);
    Image out(surface.width, surface.height, 3);
    for (int v = 0; v < surface.height; ++v) blur.row(v, out.row(v));
    return out;
}

TEST(ForwardPsfBlur, ALeanMovesLightWithoutMakingIt) {
    // A lit patch (a Gaussian of 4 px) in the middle of a dark plane at 2 m, every pixel with
    // the same lean l: each receiver p gathers K(p - q) (1 + l . (q - p)), so the light the
    // patch sends stays the same (K is symmetric) and its centroid moves by -l times the
    // blurred scales' sum_j W_j sigma_j^2 over all the light.
    const int W = 321, H = 241;
    const float d = 2.0f;
    ForwardPsfBlur blur = testing::turbid_blur(40.0, W, H);
    Image surface(W, H, 3), d2(W, H, 1, d), lean(W, H, 2);
    const double cu = 160.0, cv = 120.0;
    for (int v = 0; v < H; ++v) {
        for (int u = 0; u < W; ++u) {
            const double g = std::exp(-((u - cu) * (u - cu) + (v - cv) * (v - cv)) / 32.0);
            for (int c = 0; c < 3; ++c) surface.at(u, v, c) = float(g);
        }
    }
    const float lu = 0.004f, lv = -0.0025f;
    for (int i = 0; i < W * H; ++i) lean.data[2 * i] = lu, lean.data[2 * i + 1] = lv;
    const Image off = blurred(blur, surface, d2, nullptr);
    const Image on = blurred(blur, surface, d2, &lean);
    const ForwardPsf& psf = blur.psf();
    for (int c = 0; c < 3; ++c) {
        double s_off = 0.0, s_on = 0.0, mu = 0.0, mv = 0.0;
        for (int v = 0; v < H; ++v) {
            for (int u = 0; u < W; ++u) {
                s_off += off.at(u, v, c);
                s_on += on.at(u, v, c);
                mu += (on.at(u, v, c) - off.at(u, v, c)) * (u - cu);
                mv += (on.at(u, v, c) - off.at(u, v, c)) * (v - cv);
            }
        }
        double second = 0.0;  // sum_j W_j sigma_j^2 (px^2): the optics' weights, not the blur's
        for (int j = 1; j < psf.scales(); ++j)
            second += psf.weight(j, d)[c] * psf.sigma_px(j) * psf.sigma_px(j);
        const double total = psf.total(d)[c];
        std::printf(
            "channel %d: light with / without the lean %.5f; centroid moved (%.3f, %.3f) "
            "px, expected (%.3f, %.3f)\n",
            c, s_on / s_off, mu / s_off, mv / s_off, -lu * second / total, -lv * second / total);
        // the light beyond the frame's edges (the widest scales) is not counted in either
        EXPECT_NEAR(s_on / s_off, 1.0, 1e-4) << c;
        EXPECT_NEAR(mu / s_off, -lu * second / total, 0.02 * lu * second / total) << c;
        EXPECT_NEAR(mv / s_off, -lv * second / total, 0.02 * -lv * second / total) << c;
    }
}

TEST(ForwardPsfBlur, ALeanLeavesAUniformSurfaceUniform) {
    // The lean moves light along the surface's light's gradient: a uniform surface has none.
    // 12 x 9 px: scales blurred at full resolution, their moments too.
    for (const int W : {160, 12}) {
        const int H = W * 9 / 16;
        ForwardPsfBlur blur = testing::turbid_blur(0.75 * W, W, H);
        Image surface(W, H, 3, 0.5f), d2(W, H, 1, 3.0f), lean(W, H, 2);
        for (int i = 0; i < W * H; ++i) {
            lean.data[2 * i] = 0.01f * float(i % W - W / 2) / float(W);
            lean.data[2 * i + 1] = -0.008f;
        }
        const Image off = blurred(blur, surface, d2, nullptr);
        const Image on = blurred(blur, surface, d2, &lean);
        double worst = 0.0;
        for (std::size_t i = 0; i < on.data.size(); ++i)
            worst = std::max(worst, double(std::abs(on.data[i] - off.data[i]) / off.data[i]));
        EXPECT_LE(worst, 1e-5) << W << " x " << H;
    }
}

}  // namespace
}  // namespace deepsea
