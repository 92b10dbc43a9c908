// The runtime's phase-function forward scatter (forward_psf_blur.h) by its properties: a
// uniform surface at one distance stays uniform at the weights' total (no light lost or made
// at the image's edges), an impulse spreads as the scales' Gaussian mixture says, and pixels
// without a surface send nothing.

#include "deepsea/runtime/forward_psf_blur.h"

#include <gtest/gtest.h>

#include <cmath>

#include "deepsea/optics/jerlov.h"
#include "deepsea/optics/water.h"

namespace deepsea {
namespace {

Water coastal() {
    Water w = jerlov_water("3C");
    w.forward = phase_function_forward_scatter();
    return w;
}

Image spread(ForwardPsfBlur& blur, const Image& surface, const Image& d2) {
    blur.prepare(surface, d2);
    Image out(surface.width, surface.height, 3);
    for (int v = 0; v < surface.height; ++v) blur.row(v, out.row(v));
    return out;
}

TEST(ForwardPsfBlur, AUniformSurfaceStaysUniformAtTheTotalWeight) {
    const int W = 160, H = 90;
    ForwardPsfBlur blur(ForwardPsf(coastal(), 120.0, W, H));
    Image surface(W, H, 3), d2(W, H, 1, 3.0f);
    for (int i = 0; i < W * H; ++i) {
        surface.data[3 * i] = 0.2f;
        surface.data[3 * i + 1] = 0.5f;
        surface.data[3 * i + 2] = 1.0f;
    }
    const Image out = spread(blur, surface, d2);
    const Rgb total = blur.psf().total(3.0);
    for (int i = 0; i < W * H; ++i) {
        ASSERT_NEAR(out.data[3 * i], 0.2 * total.r, 2e-3 * total.r) << "pixel " << i;
        ASSERT_NEAR(out.data[3 * i + 1], 0.5 * total.g, 2e-3 * total.g) << "pixel " << i;
        ASSERT_NEAR(out.data[3 * i + 2], 1.0 * total.b, 2e-3 * total.b) << "pixel " << i;
    }
}

TEST(ForwardPsfBlur, ATinyImageBlursAtFullResolutionAndStaysUniform) {
    // Under 16 px a side no grid is coarse enough, so every scale is blurred at full
    // resolution and summed there (the path larger images never take).
    const int W = 12, H = 9;
    ForwardPsfBlur blur(ForwardPsf(coastal(), 10.0, W, H));
    ASSERT_EQ(ForwardPsfBlur::level_factor(1.0, W, H), 1);
    Image surface(W, H, 3), d2(W, H, 1, 2.0f);
    for (int i = 0; i < W * H; ++i) {
        surface.data[3 * i] = 0.3f;
        surface.data[3 * i + 1] = 0.6f;
        surface.data[3 * i + 2] = 0.9f;
    }
    const Image out = spread(blur, surface, d2);
    const Rgb total = blur.psf().total(2.0);
    for (int i = 0; i < W * H; ++i) {
        ASSERT_NEAR(out.data[3 * i], 0.3 * total.r, 2e-3 * total.r) << "pixel " << i;
        ASSERT_NEAR(out.data[3 * i + 1], 0.6 * total.g, 2e-3 * total.g) << "pixel " << i;
        ASSERT_NEAR(out.data[3 * i + 2], 0.9 * total.b, 2e-3 * total.b) << "pixel " << i;
    }
    // a second frame gives the same: the sums are cleared between frames
    const Image again = spread(blur, surface, d2);
    EXPECT_EQ(again.data, out.data);
}

TEST(ForwardPsfBlur, AnImpulseSpreadsAsTheMixture) {
    const int W = 257, H = 257, c = 128;
    ForwardPsfBlur blur(ForwardPsf(coastal(), 300.0, W, H));
    Image surface(W, H, 3), d2(W, H, 1, 0.0f);
    surface.at(c, c, 1) = 1.0f;
    d2.at(c, c) = 2.0f;
    const Image out = spread(blur, surface, d2);
    const ForwardPsf& psf = blur.psf();
    for (const double R : {1.5, 4.0, 12.0, 40.0}) {
        double got = 0.0, expect = 0.0;
        for (int v = 0; v < H; ++v) {
            for (int u = 0; u < W; ++u) {
                if (std::hypot(u - c, v - c) <= R) got += out.at(u, v, 1);
            }
        }
        // each scale as the reference blurs: a sampled Gaussian normalised to 1
        for (int j = 0; j < psf.scales(); ++j) {
            const double s = psf.sigma_px(j);
            double in = 0.0, all = 0.0;
            for (int y = -c; y <= c; ++y) {
                for (int x = -c; x <= c; ++x) {
                    const double g = s > 0.0 ? std::exp(-0.5 * (x * x + y * y) / (s * s))
                                             : double(x == 0 && y == 0);
                    all += g;
                    in += std::hypot(x, y) <= R ? g : 0.0;
                }
            }
            expect += psf.weight(j, 2.0).g * in / all;
        }
        // 6 %: box-downsampling moves a lone pixel to its block's centre (here 0.5 .. 63.5 px
        // off for the wide scales); extended surfaces average that out.
        EXPECT_NEAR(got, expect, 0.06 * expect) << "radius " << R;
    }
    // Nothing comes from pixels without a surface: an all-open-water frame is black.
    const Image none = spread(blur, surface, Image(W, H, 1, 0.0f));
    for (const float x : none.data) ASSERT_EQ(x, 0.0f);
}

}  // namespace
}  // namespace deepsea
