// The forward scatter's scene beyond the frame's corners (forward_psf_blur.h, EdgeFalloff):
// a frame lit by a real rig against the same pixels of a frame three times wider.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deepsea/optics/forward_transport.h"
#include "deepsea/optics/lamp_field.h"
#include "deepsea/runtime/forward_psf_blur.h"
#include "deepsea/runtime/lamps.h"
#include "runtime_fixtures.h"

namespace deepsea {
namespace {

/// validate.py's two spots: sigma 35 degrees, toed in 30.7 degrees.
Rig two_spots() {
    Rig rig;
    for (int s : {-1, 1}) {
        Light l;
        l.position = {0.5 * s, 0.0, 0.0};
        l.direction = normalize(Vec3(-s * 0.510586, 0.0, 0.859826));
        l.intensity = s < 0 ? Rgb(1.0, 0.9, 0.8) : Rgb(0.8, 0.9, 1.0);
        l.rid.sigma_deg = 35.0;
        rig.lights.push_back(l);
    }
    return rig;
}

/// A plane z metres away seen by cam, lit by lamps: surface radiance J/pi E and distance.
void plane_frame(const Camera& cam, double z, const IrradianceSource& lamps, Image& surface,
                 Image& d2) {
    const int W = cam.width, H = cam.height;
    surface = Image(W, H, 3);
    d2 = Image(W, H, 1);
    const Rgb albedo(0.7, 0.55, 0.4);
    std::vector<float> px(W), py(W), pz(W, float(z)), nx(W, 0.0f), ny(W, 0.0f), nz(W, -1.0f),
        e(3 * std::size_t(W));
    for (int v = 0; v < H; ++v) {
        for (int u = 0; u < W; ++u) {
            px[u] = float(z * cam.ray_x(u));
            py[u] = float(z * cam.ray_y(v));
            d2.at(u, v) = float(std::hypot(double(px[u]), double(py[u]), z));
        }
        const RowGeometry g{v, W, px.data(), py.data(), pz.data(), nx.data(), ny.data(), nz.data()};
        lamps.irradiance_row(g, e.data());
        for (int u = 0; u < W; ++u)
            for (int c = 0; c < 3; ++c)
                surface.at(u, v, c) = float(albedo[c] / M_PI * e[std::size_t(c) * W + u]);
    }
}

/// validate.py's coastal water (c 0.35-0.6, b 0.3, HG 0.9), forward scatter from the phase
/// function.
Water coastal_water() { return testing::hg_water(Rgb(0.6, 0.4, 0.35), Rgb(0.3, 0.3, 0.3), 0.9); }

/// validate.py's auv rig: a 20 degree lamp 0.7 m above and 0.2 m behind the camera, a warm
/// 15 degree side lamp.
Rig auv() {
    Rig rig;
    Light top;
    top.position = {0.0, -0.7, -0.2};
    top.direction = normalize(Vec3(0.0, 0.25, 1.0));
    top.intensity = {1.0, 1.0, 1.0};
    top.rid.sigma_deg = 20.0;
    Light side;
    side.position = {0.6, 0.0, 0.0};
    side.direction = normalize(Vec3(-0.2, 0.0, 1.0));
    side.intensity = {1.0, 0.8, 0.6};
    side.rid.sigma_deg = 15.0;
    rig.lights = {top, side};
    return rig;
}

/// The largest differences, over channels, of a W x H frame's forward scatter with its falloff
/// beyond the frame from the same pixels of a frame three times wider (its own falloff beyond;
/// with true_angles, ForwardPsfBlur::set_camera, a quarter wider):
/// a plane z metres away lit by the rig (with `fields`, their scattered light too), 64.5
/// degrees across. Both blur with the small frame's scales.
struct Worst {
    double bin8 = 0.0, pixel = 0.0;
};
Worst framed_against_wider(const Water& w, const Rig& rig, int W, int H, double z,
                           const std::vector<LampField>& fields = {}, bool true_angles = false) {
    ForwardTransportSettings s;
    s.paths = 1 << 12;
    const ForwardPsfTable table = trace_forward_psf(w, forward_psf_depths(8.0, 16), s);
    const double fx = 0.5 * W / std::tan(64.5 / 2 * M_PI / 180);
    const Camera small{W, H, fx, fx, 0.5 * (W - 1), 0.5 * (H - 1)};
    // (at true angles a quarter wider: three times wider is 124 degrees across, where the
    // equidistant grid's corners pass 90 degrees)
    const int X0 = true_angles ? W / 8 : W, Y0 = true_angles ? H / 8 : H;
    const int WW = W + 2 * X0, HH = H + 2 * Y0;
    const Camera wide{WW, HH, fx, fx, 0.5 * (WW - 1), 0.5 * (HH - 1)};
    const AnalyticLamps lamps(rig, w, fields);
    const ForwardPsf psf(table, w, fx, W, H);
    const auto forward = [&](const Camera& cam, int x0, int y0) {
        Image surface, d2;
        plane_frame(cam, z, lamps, surface, d2);
        EdgeFalloff beyond;
        edge_falloff(cam, Image(cam.width, cam.height, 1, float(z)), lamps, psf, beyond);
        ForwardPsfBlur blur(psf);
        if (true_angles) blur.set_camera(cam.fx, cam.fy, cam.cx, cam.cy);
        blur.prepare(surface, d2, &beyond);
        Image out(W, H, 3);
        std::vector<float> row(3 * std::size_t(cam.width));
        for (int v = 0; v < H; ++v) {
            blur.row(v + y0, row.data());
            for (int u = 0; u < W; ++u)
                for (int c = 0; c < 3; ++c) out.at(u, v, c) = row[3 * std::size_t(u + x0) + c];
        }
        return out;
    };
    const Image truth = forward(wide, X0, Y0), framed = forward(small, 0, 0);
    Worst worst;
    for (int c = 0; c < 3; ++c) {
        for (int by = 0; by < H / 8; ++by) {
            for (int bx = 0; bx < W / 8; ++bx) {
                double a = 0.0, b = 0.0;
                for (int v = by * 8; v < by * 8 + 8; ++v) {
                    for (int u = bx * 8; u < bx * 8 + 8; ++u) {
                        a += framed.at(u, v, c);
                        b += truth.at(u, v, c);
                        worst.pixel = std::max(
                            worst.pixel, std::fabs(framed.at(u, v, c) / truth.at(u, v, c) - 1.0));
                    }
                }
                worst.bin8 = std::max(worst.bin8, std::fabs(a / b - 1.0));
            }
        }
    }
    return worst;
}

}  // namespace

TEST(ForwardPsfCorners, AFrameLitByTwoSpotsSeesWhatAWiderFrameSees) {
    // validate.py's turbid-plane scene: the plane 2 m away, 64 x 48. The corners' 8 x 8 bins
    // were +1.8 % and their pixels +12 %, the other border pixels +5-7 %, while the upsampling
    // held every grid flat beyond its outer cells.
    const Worst worst = framed_against_wider(testing::turbid_water(), two_spots(), 64, 48, 2.0);
    std::printf("8x8 bins within %.2f %%, pixels within %.2f %%\n", 100 * worst.bin8,
                100 * worst.pixel);
    EXPECT_LT(worst.bin8, 0.01);    // 0.4 %
    EXPECT_LT(worst.pixel, 0.025);  // 1.1 %, a corner's
}

TEST(ForwardPsfCorners, AFrameLitByTheAuvRigSeesWhatAWiderFrameSees) {
    // validate.py's coastal-auv scene: the plane 3 m away, 160 x 120, lamps off the view's
    // axes (their falloffs beyond a row and a column need not multiply into the corner's),
    // with and without their scattered light (lamp fields). With every grid held flat beyond
    // its outer cells: 8 x 8 bins +6.9 %, corner pixels +20 %. Now the worst pixels are on the
    // right border, by the side lamp (red), the corners' within 1.2 %.
    const Water w = coastal_water();
    LampFieldSettings ls;
    ls.nr = 10;
    ls.ntheta = 13;
    ls.r0 = 0.05;
    ls.r_max = 12.0;
    ls.samples = 256;
    std::vector<LampField> fields;
    for (const Light& L : auv().lights) fields.push_back(bake_lamp_field(L, w, ls));
    for (const bool scattered : {false, true}) {
        const Worst worst = framed_against_wider(w, auv(), 160, 120, 3.0,
                                                 scattered ? fields : std::vector<LampField>{});
        std::printf("8x8 bins within %.2f %%, pixels within %.2f %%\n", 100 * worst.bin8,
                    100 * worst.pixel);
        EXPECT_LT(worst.bin8, 0.015);   // 0.87 % and 1.05 %
        EXPECT_LT(worst.pixel, 0.045);  // 3.42 % and 3.12 %
    }
}

TEST(ForwardPsfCorners, AtTrueAnglesAFrameSeesWhatAWiderFrameSees) {
    // The wide scales in the equidistant image (ForwardPsfBlur::set_camera): its cells beyond
    // the frame continue the border as the falloff says. Against a frame a quarter wider
    // (measured: two spots 1.7 % per 8x8 bin, 2.8 % per pixel; the auv rig 5.5 % and 5.9 %, its
    // border pixels above the wider frame's; the pinhole grids 0.3 %, 1.0 % and 1.5 %, 3.9 %).
    const Water coastal = coastal_water();
    const Worst spots =
        framed_against_wider(testing::turbid_water(), two_spots(), 64, 48, 2.0, {}, true);
    const Worst rig = framed_against_wider(coastal, auv(), 160, 120, 3.0, {}, true);
    std::printf(
        "two spots: 8x8 bins within %.2f %%, pixels within %.2f %%; auv rig: %.2f %%, "
        "%.2f %%\n",
        100 * spots.bin8, 100 * spots.pixel, 100 * rig.bin8, 100 * rig.pixel);
    EXPECT_LT(spots.bin8, 0.025);
    EXPECT_LT(spots.pixel, 0.04);
    EXPECT_LT(rig.bin8, 0.07);
    EXPECT_LT(rig.pixel, 0.08);
}

}  // namespace deepsea
