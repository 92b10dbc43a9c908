// The runtime's phase-function forward scatter (forward_psf_blur.h) by its properties: a
// uniform surface at one distance stays uniform at the weights' total (no light lost or made
// at the image's edges), an impulse spreads as the scales' Gaussian mixture says, and pixels
// without a surface send nothing.

#include "deepsea/runtime/forward_psf_blur.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "deepsea/optics/forward_transport.h"
#include "deepsea/optics/jerlov.h"
#include "deepsea/optics/water.h"
#include "deepsea/optics/water_presets.h"
#include "runtime_fixtures.h"

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

/// Spreads a uniform surface of colour `rgb` at distance d over a W x H image; every pixel
/// must come out as rgb times the total weight (the light stays where a uniform surface sends
/// it), within 0.2 %. Returns the spread image.
Image expect_uniform(ForwardPsfBlur& blur, int W, int H, const Rgb& rgb, float d) {
    Image surface(W, H, 3), d2(W, H, 1, d);
    for (int i = 0; i < W * H; ++i) {
        for (int c = 0; c < 3; ++c) surface.data[3 * i + c] = float(rgb[c]);
    }
    const Image out = spread(blur, surface, d2);
    const Rgb total = blur.psf().total(d);
    double worst = 0.0;  // |out - rgb total| / total, the largest over pixels and channels
    int at = -1;
    for (int i = 0; i < W * H; ++i) {
        for (int c = 0; c < 3; ++c) {
            const double e = std::abs(out.data[3 * i + c] - rgb[c] * total[c]) / total[c];
            if (e > worst) worst = e, at = i;
        }
    }
    EXPECT_LE(worst, 2e-3) << "at pixel " << at;
    return out;
}

TEST(ForwardPsfBlur, AUniformSurfaceStaysUniformAtTheTotalWeight) {
    const int W = 160, H = 90;
    ForwardPsfBlur blur(ForwardPsf(coastal(), 120.0, W, H));
    expect_uniform(blur, W, H, Rgb(0.2, 0.5, 1.0), 3.0f);
}

TEST(ForwardPsfBlur, OddSizesStayUniformToo) {
    // Rows of four pixels at a time and their remainder, blocks cut short at the right and
    // bottom edges at every level of the block sums: 161 x 91 px.
    const int W = 161, H = 91;
    ForwardPsfBlur blur(ForwardPsf(coastal(), 120.0, W, H));
    expect_uniform(blur, W, H, Rgb(1.0, 0.4, 0.1), 4.0f);
}

TEST(ForwardPsfBlur, ATinyImageBlursAtFullResolutionAndStaysUniform) {
    // Under 16 px a side no grid is coarse enough, so every scale is blurred at full
    // resolution and summed there (the path larger images never take).
    const int W = 12, H = 9;
    ForwardPsfBlur blur(ForwardPsf(coastal(), 10.0, W, H));
    ASSERT_EQ(ForwardPsfBlur::level_factor(1.0, W, H), 1);
    const Image out = expect_uniform(blur, W, H, Rgb(0.3, 0.6, 0.9), 2.0f);
    // a second frame gives the same: the sums are cleared between frames
    const Image again = expect_uniform(blur, W, H, Rgb(0.3, 0.6, 0.9), 2.0f);
    EXPECT_EQ(again.data, out.data);
}

TEST(ForwardPsfBlur, ATransportTableBlursAsItsWeightsSay) {
    // The weights fitted to a forward-scatter table (optics/forward_transport.h): piecewise
    // linear in distance, spanned by the blur's basis to its tolerance for tables, and a
    // uniform surface stays uniform at their total.
    const int W = 160, H = 90;
    ForwardTransportSettings s;
    s.paths = 1 << 12;
    const Water w = coastal();
    ForwardPsfBlur blur(
        ForwardPsf(trace_forward_psf(w, forward_psf_depths(8.0, 16), s), w, 120.0, W, H));
    ASSERT_TRUE(blur.psf().from_transport());
    expect_uniform(blur, W, H, Rgb(0.2, 0.5, 1.0), 3.0f);
    for (const double d : {0.3, 1.1, 1.7, 2.9}) {  // within the frame's table (to 3 m)
        const Rgb total = blur.psf().total(d);
        for (int j = 0; j < blur.psf().scales(); ++j) {
            const Rgb a = blur.applied_weight(j, d), e = blur.psf().weight(j, d);
            // the basis spans a table's weights to 1e-3 of the largest total (forward_psf_blur.cpp)
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], e[c], 2e-3 * total[c]) << j << " " << d;
        }
    }
}

TEST(ForwardPsfBlur, EveryScaleIsWeighedAsTheOpticsSay) {
    // The blurred scales are weighed through a few basis functions (column_basis.h): each
    // scale's weight must still be the optics' own, to the table's interpolation, at every
    // distance the frame holds, in clear and turbid water.
    for (const char* type : {"IB", "3C", "5C"}) {
        Water w = jerlov_water(type);
        w.forward = phase_function_forward_scatter();
        const int W = 400, H = 300;
        ForwardPsfBlur blur(ForwardPsf(w, 300.0, W, H));
        Image surface(W, H, 3, 0.5f), d2(W, H, 1, 0.0f);
        for (int v = 0; v < H; ++v) {
            for (int u = 0; u < W; ++u) d2.at(u, v) = 0.5f + 9.5f * float(u) / float(W - 1);
        }
        blur.prepare(surface, d2);
        const ForwardPsf& psf = blur.psf();
        double worst = 0.0;  // |applied - optics| / the channel's total, the largest
        for (double d = 0.5; d <= 10.0; d += 0.0371) {
            const Rgb total = psf.total(d);
            for (int j = 0; j < psf.scales(); ++j) {
                const Rgb got = blur.applied_weight(j, d), expect = psf.weight(j, d);
                for (int c = 0; c < 3; ++c) {
                    worst = std::max(worst, std::abs(got[c] - expect[c]) / total[c]);
                }
            }
        }
        // (measured 2-4e-6: the table's interpolation and the basis's 1e-6 of the total)
        EXPECT_LE(worst, 2e-5) << "Jerlov " << type;
    }
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

/// The plane scene at 400 px (a 0.3 m plane with a nearer box), its open water (NaN, inf, -1,
/// 0) as 0 and every seventh row open water too: rows that alternate between whole blocks on
/// one surface and none, whose weighing is split between threads by bands.
std::pair<Image, Image> striped_plane(const Camera& cam) {
    const testing::PlaneScene p = testing::plane_scene(cam, 0.3);
    Image d2 = p.depth;
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const float z = d2.at(u, v);
            if (v % 7 == 0 || !(z > 0.0f && z < 1e30f)) d2.at(u, v) = 0.0f;
        }
    }
    return {p.rgb, d2};
}

}  // namespace

TEST(ForwardPsfBlur, EveryRunGivesTheSameBits) {
    // the weighing's bands run in parallel with per-thread scratch: twenty runs on all the
    // machine's threads must agree bit for bit (with the distances sanitised, as the
    // compositor hands them over: raw NaN and inf made the farthest surface, and so the
    // frame's table, depend on the threads' split)
    const Camera cam{400, 400, 300.0, 300.0, 200.0, 200.0};
    const auto [surface, d2] = striped_plane(cam);
    Water clear = water_preset("deep:clear");
    clear.forward = phase_function_forward_scatter();
    for (const Water& water : {clear, coastal()}) {
        const ForwardPsf psf(water, cam.fx, cam.width, cam.height);
        ForwardPsfBlur ref(psf);
        const Image first = spread(ref, surface, d2);
        for (int run = 0; run < 20; ++run) {
            ForwardPsfBlur blur(psf);
            const Image again = spread(blur, surface, d2);
            ASSERT_EQ(again.data, first.data) << "run " << run;
        }
    }
}

}  // namespace deepsea
