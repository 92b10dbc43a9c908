// The fast forward-scatter blur by its properties: it preserves a constant image (normalised
// over in-image pixels), an impulse spreads with the requested variance at every level
// (full resolution and downsampled), unblurred pixels stay 0, and the scale applies.

#include "deepsea/runtime/forward_blur.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace deepsea {
namespace {

/// Every row of the blur, as an image.
Image blur(const Image& in, const Image& s, float scale) {
    ForwardBlur fb;
    fb.prepare(in, s, scale);
    Image out(in.width, in.height, 3);
    for (int v = 0; v < in.height; ++v) fb.blend_row(v, s.row(v), out.row(v));
    return out;
}

TEST(ForwardBlur, KeepsAConstantImageEverywhere) {
    Image in(97, 61, 3);
    for (int i = 0; i < 97 * 61; ++i) {
        in.data[3 * i] = 0.2f;
        in.data[3 * i + 1] = 0.5f;
        in.data[3 * i + 2] = 1.0f;
    }
    Image s(97, 61, 1);
    for (int v = 0; v < 61; ++v)
        for (int u = 0; u < 97; ++u) s.at(u, v) = 0.5f + 7.0f * u / 96.0f;  // 0.5 .. 7.5 px
    const Image out = blur(in, s, 1.0f);
    for (int i = 0; i < 97 * 61; ++i) {
        ASSERT_NEAR(out.data[3 * i], 0.2f, 1e-4f) << "pixel " << i;
        ASSERT_NEAR(out.data[3 * i + 1], 0.5f, 1e-4f) << "pixel " << i;
        ASSERT_NEAR(out.data[3 * i + 2], 1.0f, 1e-4f) << "pixel " << i;
    }
}

/// Sum and variance (x and y) of the blurred impulse at the centre of a square image.
void impulse_moments(double sigma, float scale, double& sum, double& var) {
    const int n = 161, c = n / 2;
    Image in(n, n, 3);
    in.at(c, c, 1) = 1.0f;
    Image s(n, n, 1, float(sigma / scale));
    const Image out = blur(in, s, scale);
    sum = 0.0;
    double m2 = 0.0;
    for (int v = 0; v < n; ++v) {
        for (int u = 0; u < n; ++u) {
            const double w = out.at(u, v, 1);
            sum += w;
            m2 += w * ((u - c) * (u - c) + (v - c) * (v - c));
            ASSERT_EQ(out.at(u, v, 0), 0.0f);  // channels stay apart
        }
    }
    var = m2 / sum / 2.0;
}

TEST(ForwardBlur, ImpulseSpreadsWithTheRequestedSigma) {
    // 1.5 px is blurred at full resolution; 3, 6 and 11 px on downsampled copies.
    for (double sigma : {1.5, 3.0, 6.0, 11.0}) {
        double sum = 0.0, var = 0.0;
        impulse_moments(sigma, 1.0f, sum, var);
        EXPECT_NEAR(sum, 1.0, 0.02) << "sigma " << sigma;
        EXPECT_NEAR(std::sqrt(var), sigma, 0.08 * sigma) << "sigma " << sigma;
    }
}

TEST(ForwardBlur, ScaleMultipliesSigma) {
    double sum = 0.0, var = 0.0;
    impulse_moments(5.0, 25.0f, sum, var);  // s = 0.2 per pixel, scale 25
    EXPECT_NEAR(std::sqrt(var), 5.0, 0.4);
}

TEST(ForwardBlur, PixelsWithoutSigmaStayBlack) {
    Image in(40, 30, 3, 1.0f);
    Image s(40, 30, 1, 2.0f);
    for (int v = 0; v < 30; ++v) s.at(7, v) = 0.0f;
    const Image out = blur(in, s, 1.0f);
    for (int v = 0; v < 30; ++v) {
        EXPECT_EQ(out.at(7, v, 0), 0.0f);
        EXPECT_NEAR(out.at(8, v, 0), 1.0f, 1e-4f);
    }
    const Image none = blur(in, Image(40, 30, 1), 1.0f);  // no pixel blurred at all
    for (float x : none.data) ASSERT_EQ(x, 0.0f);
}

TEST(ForwardBlur, SigmaIsCappedAtTheImageSize) {
    // A surface 1e5 m away asks for a blur of millions of pixels: it gets the cap (here 40 px,
    // a flat image-wide mean) in bounded time, and a constant image stays constant.
    Image in(40, 30, 3, 0.5f);
    Image s(40, 30, 1, 3e6f);
    s.at(3, 4) = std::numeric_limits<float>::infinity();
    const Image out = blur(in, s, 1.0f);
    for (float x : out.data) ASSERT_NEAR(x, 0.5f, 1e-4f);
}

}  // namespace
}  // namespace deepsea
