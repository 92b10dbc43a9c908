// The forward scatter's wide scales at true angles (ForwardPsfBlur::set_camera: their grids in
// the equidistant image): a uniform surface stays uniform (the warp moves light, it makes and
// loses none), and a lit patch's light spreads as on a pinhole grid at the image centre and
// wider off axis, radially by about 1 / cos^2 and across by about tan / theta.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "deepsea/optics/forward_transport.h"
#include "deepsea/runtime/forward_psf_blur.h"
#include "equidistant.h"
#include "runtime_fixtures.h"

namespace deepsea {
namespace {

TEST(ForwardPsfWarp, TheMapAndItsStretchAreTheEquidistantImages) {
    // atan(r) / r to 3e-5 (the polynomial's 1e-5 rad; 0.02 px at 800 px off axis), and J J^T the
    // map's own Jacobian (central differences of rho = atan(r) along the radius) squared
    for (double r = 0.0; r < 20.0; r += 0.013) {
        const double exact = r > 0.0 ? std::atan(r) / r : 1.0;
        EXPECT_NEAR(equidistant::atan_ratio(float(r * r)), exact, 3e-5 * exact) << r;
    }
    for (const double a : {0.0, 0.3, -0.62, 1.4}) {
        for (const double b : {0.0, -0.45, 0.2}) {
            // J = d(pinhole) / d(equidistant): the inverse of the map's Jacobian at (a, b)
            const auto map = [](double x, double y, double& ex, double& ey) {
                const double r = std::hypot(x, y), s = r > 0.0 ? std::atan(r) / r : 1.0;
                ex = s * x;
                ey = s * y;
            };
            const double h = 1e-5;
            double xp, yp, xm, ym, m[2][2];
            map(a + h, b, xp, yp);
            map(a - h, b, xm, ym);
            m[0][0] = (xp - xm) / (2 * h), m[1][0] = (yp - ym) / (2 * h);
            map(a, b + h, xp, yp);
            map(a, b - h, xm, ym);
            m[0][1] = (xp - xm) / (2 * h), m[1][1] = (yp - ym) / (2 * h);
            const double det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            const double j[2][2] = {{m[1][1] / det, -m[0][1] / det},
                                    {-m[1][0] / det, m[0][0] / det}};
            const double xx = j[0][0] * j[0][0] + j[0][1] * j[0][1];
            const double xy = j[0][0] * j[1][0] + j[0][1] * j[1][1];
            const double yy = j[1][0] * j[1][0] + j[1][1] * j[1][1];
            float sxx = 0.0f, sxy = 0.0f, syy = 0.0f;
            equidistant::stretch(float(a), float(b), sxx, sxy, syy);
            EXPECT_NEAR(sxx, xx, 1e-3 * xx) << a << " " << b;
            EXPECT_NEAR(sxy, xy, 1e-3 * xx) << a << " " << b;
            EXPECT_NEAR(syy, yy, 1e-3 * yy) << a << " " << b;
        }
    }
}

Image blurred(ForwardPsfBlur& blur, const Image& surface, const Image& d2,
              const Image* lean = nullptr) {
    blur.prepare(surface, d2, nullptr, -1.0, lean);
    Image out(surface.width, surface.height, 3);
    for (int v = 0; v < surface.height; ++v) blur.row(v, out.row(v));
    return out;
}

TEST(ForwardPsfWarp, AUniformSurfaceStaysUniform) {
    // coastal-auv's camera (160 x 120, 64.5 degrees across) and a 64 x 48 one (its grids of
    // factor 4 warped), with and without a lean
    for (const int W : {160, 64}) {
        const int H = W * 3 / 4;
        const double fx = 0.5 * W / std::tan(64.5 / 2 * M_PI / 180);
        ForwardPsfBlur blur = testing::turbid_blur(fx, W, H);
        blur.set_camera(fx, fx, 0.5 * (W - 1), 0.5 * (H - 1));
        Image surface(W, H, 3, 0.5f), d2(W, H, 1, 2.0f), lean(W, H, 2);
        for (int i = 0; i < W * H; ++i) {
            lean.data[2 * i] = 0.01f * float(i % W - W / 2) / float(W);
            lean.data[2 * i + 1] = -0.008f;
        }
        const Rgb total = blur.psf().total(2.0);
        const Image* leans[] = {nullptr, &lean};
        for (const Image* l : leans) {
            const Image out = blurred(blur, surface, d2, l);
            double worst = 0.0;
            for (int i = 0; i < W * H; ++i) {
                for (int c = 0; c < 3; ++c) {
                    worst = std::max(worst, std::abs(out.data[3 * i + c] / (0.5 * total[c]) - 1));
                }
            }
            EXPECT_LE(worst, 2e-3) << W << " x " << H << (l ? ", with a lean" : "");
        }
    }
}

/// The second moments (px^2) of a blurred lit patch's light about its centre (u0, v0),
/// radially (along u) and across (along v), within `reach` px, outside its 3 px core (the
/// unblurred scale's and the narrowest scales' light, the same with and without the warp).
struct Spread {
    double along = 0.0, across = 0.0;
};
Spread spread(const Image& f, int u0, int v0, int reach) {
    double s = 0.0, su = 0.0, sv = 0.0;
    for (int v = v0 - reach; v <= v0 + reach; ++v) {
        for (int u = u0 - reach; u <= u0 + reach; ++u) {
            const double du = u - u0, dv = v - v0, r2 = du * du + dv * dv;
            if (r2 <= 9.0 || r2 > double(reach) * reach) continue;
            const double x = f.at(u, v, 1);
            s += x;
            su += x * du * du;
            sv += x * dv * dv;
        }
    }
    return {su / s, sv / s};
}

TEST(ForwardPsfWarp, ThePatchSpreadsOverTrueAngles) {
    // A 321 x 241 frame 90 degrees across, a lit patch (a Gaussian of 2 px) on a dark plane at
    // 2 m, at the centre and 35 degrees off axis along u. At the centre the equidistant image is
    // the pinhole's; 35 degrees off, a radian spans 1 / cos^2 = 1.49 times the pixels radially
    // and tan / theta = 1.15 across, so the warped scales' second moments widen by 2.22 and
    // 1.31 there (and the pinhole blur's not at all).
    const int W = 321, H = 241, reach = 40;
    const double fx = 160.0, cx = 160.0, cy = 120.0;
    const int off = int(std::lround(cx + fx * std::tan(35.0 * M_PI / 180)));
    Spread warped_at[2], pinhole_at[2];
    for (const int u0 : {int(cx), off}) {
        Image surface(W, H, 3), d2(W, H, 1, 2.0f);
        for (int v = 0; v < H; ++v) {
            for (int u = 0; u < W; ++u) {
                const double g = std::exp(-((u - u0) * (u - u0) + (v - cy) * (v - cy)) / 8.0);
                for (int c = 0; c < 3; ++c) surface.at(u, v, c) = float(g);
            }
        }
        ForwardPsfBlur pinhole = testing::turbid_blur(fx, W, H),
                       warped = testing::turbid_blur(fx, W, H);
        warped.set_camera(fx, fx, cx, cy);
        const Spread a = spread(blurred(pinhole, surface, d2), u0, int(cy), reach);
        const Spread b = spread(blurred(warped, surface, d2), u0, int(cy), reach);
        pinhole_at[u0 == off] = a;
        warped_at[u0 == off] = b;
        std::printf(
            "patch at u = %d: second moments along u, across (px^2): pinhole %.1f, %.1f; "
            "warped %.1f, %.1f\n",
            u0, a.along, a.across, b.along, b.across);
    }
    // At the centre the warped blur is the pinhole's (measured: within 0.8 %).
    EXPECT_NEAR(warped_at[0].along / pinhole_at[0].along, 1.0, 0.02);
    EXPECT_NEAR(warped_at[0].across / pinhole_at[0].across, 1.0, 0.02);
    // Off axis the pinhole blur spreads as at the centre; the warped one wider along the radius
    // than across, relative to the pinhole's (measured 1.20: the window, the flat light of the
    // widest scales within it and the narrow scales, unwarped, take it from 1.69 towards 1).
    EXPECT_NEAR(pinhole_at[1].along, pinhole_at[0].along, 0.01 * pinhole_at[0].along);
    const double aniso =
        (warped_at[1].along / warped_at[1].across) / (pinhole_at[1].along / pinhole_at[1].across);
    EXPECT_GT(aniso, 1.1);
    EXPECT_LT(aniso, 2.22 / 1.31);
    EXPECT_GT(warped_at[1].along / pinhole_at[1].along, 1.1);
}

}  // namespace
}  // namespace deepsea
