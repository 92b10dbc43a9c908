// What lies beyond the frame for the forward scatter from transport (forward_psf_blur.h,
// EdgeFalloff and edge_falloff): a frame's forward scatter against a frame three times wider
// (the same camera's pixels, the scene beyond the small frame's edges in view), and the lamps'
// falloff against the optics' irradiance at the continued surface.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "deepsea/optics/direct.h"
#include "deepsea/optics/forward_transport.h"
#include "deepsea/optics/lamp_field.h"
#include "deepsea/runtime/forward_psf_blur.h"
#include "deepsea/runtime/lamps.h"
#include "runtime_fixtures.h"

namespace deepsea {
namespace {

/// Sums of F over the W x H window at (x0, y0) of a frame's surface radiance and distance:
/// the whole window, and its outer ring 4 pixels wide.
struct Sums {
    Rgb all, ring;
};
Sums forward_sums(ForwardPsfBlur& blur, const Image& surface, const Image& d2,
                  const EdgeFalloff* beyond, int x0, int y0, int W, int H) {
    blur.prepare(surface, d2, beyond);
    std::vector<float> row(3 * std::size_t(surface.width));
    Sums s;
    for (int v = y0; v < y0 + H; ++v) {
        blur.row(v, row.data());
        for (int u = x0; u < x0 + W; ++u) {
            const bool ring = u < x0 + 4 || u >= x0 + W - 4 || v < y0 + 4 || v >= y0 + H - 4;
            for (int c = 0; c < 3; ++c) {
                s.all[c] += row[3 * std::size_t(u) + c];
                if (ring) s.ring[c] += row[3 * std::size_t(u) + c];
            }
        }
    }
    return s;
}

}  // namespace

TEST(ForwardPsfEdges, AFrameWithItsFalloffSeesWhatAWiderFrameSees) {
    // A plane 2 m away in turbid water, lit in a patch about the view's centre (a Gaussian of
    // 16 px, its border 0.14-0.32 of the centre): the 64 x 48 frame's forward scatter against
    // the same pixels of a 192 x 144 frame around it. fx = 24, so that the widest Gaussian
    // (2.6 rad) is below both frames' cap and both blur with the same scales.
    const Water w = testing::turbid_water();
    ForwardTransportSettings s;
    s.paths = 1 << 12;
    const ForwardPsfTable table = trace_forward_psf(w, forward_psf_depths(8.0, 16), s);
    const double fx = 24.0, z = 2.0, cx = 95.5, cy = 71.5, sigma = 16.0;
    const int W = 64, H = 48, X0 = 64, Y0 = 48;
    const std::function<double(double, double)> dist = [&](double u, double v) {
        return z * std::sqrt(1.0 + std::pow((u - cx) / fx, 2) + std::pow((v - cy) / fx, 2));
    };
    const std::function<double(double, double)> light = [&](double u, double v) {
        return std::exp(-0.5 * (std::pow(u - cx, 2) + std::pow(v - cy, 2)) / (sigma * sigma));
    };
    const Rgb albedo(0.7, 0.55, 0.4);
    const auto frame = [&](int x0, int y0, int fw, int fh, Image& surface, Image& d2) {
        surface = Image(fw, fh, 3);
        d2 = Image(fw, fh, 1);
        for (int v = 0; v < fh; ++v) {
            for (int u = 0; u < fw; ++u) {
                d2.at(u, v) = float(dist(u + x0, v + y0));
                for (int c = 0; c < 3; ++c)
                    surface.at(u, v, c) = float(albedo[c] * light(u + x0, v + y0));
            }
        }
    };
    Image ws, wd, ns, nd;
    frame(0, 0, 3 * W, 3 * H, ws, wd);
    frame(X0, Y0, W, H, ns, nd);
    ForwardPsfBlur wide(ForwardPsf(table, w, fx, 3 * W, 3 * H));
    ForwardPsfBlur small(ForwardPsf(table, w, fx, W, H));
    ASSERT_EQ(wide.psf().scales(), small.psf().scales() + 2);  // 128 and 192 px: no weight
    const Sums truth = forward_sums(wide, ws, wd, nullptr, X0, Y0, W, H);

    // The falloff the wider frame shows: radiance and total weight over the border pixel's.
    EdgeFalloff beyond;
    beyond.width = W;
    beyond.height = H;
    for (int k = 1; k <= 16; ++k) beyond.dist.push_back(float(3.5 * W * k * k / 256.0));
    const int K = beyond.samples();
    const auto fill = [&](std::vector<float>& side, int n, double du, double dv, bool rows) {
        side.assign(std::size_t(3) * n * K, 1.0f);
        for (int i = 0; i < n; ++i) {
            // the border pixel of this side, in the wider frame's pixels
            const double ub = rows ? (du < 0 ? X0 : X0 + W - 1) : X0 + i;
            const double vb = rows ? Y0 + i : (dv < 0 ? Y0 : Y0 + H - 1);
            const Rgb tb = small.psf().total(dist(ub, vb));
            for (int k = 0; k < K; ++k) {
                const double uq = ub + du * beyond.dist[k], vq = vb + dv * beyond.dist[k];
                const Rgb tq = small.psf().total(dist(uq, vq));
                for (int c = 0; c < 3; ++c)
                    side[(std::size_t(c) * n + i) * K + k] =
                        float(light(uq, vq) / light(ub, vb) * tq[c] / tb[c]);
            }
        }
    };
    fill(beyond.left, H, -1, 0, true);
    fill(beyond.right, H, 1, 0, true);
    fill(beyond.top, W, 0, -1, false);
    fill(beyond.bottom, W, 0, 1, false);

    const Sums faded = forward_sums(small, ns, nd, &beyond, 0, 0, W, H);
    const Sums clamped = forward_sums(small, ns, nd, nullptr, 0, 0, W, H);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(faded.all[c] / truth.all[c], 1.0, 0.01) << "channel " << c;
        EXPECT_NEAR(faded.ring[c] / truth.ring[c], 1.0, 0.04) << "channel " << c;
        // the borders continued unchanged (what the blur did before): +12 % on the ring
        EXPECT_GT(clamped.ring[c] / truth.ring[c], 1.08) << "channel " << c;
    }
}

TEST(ForwardPsfEdges, TheLampsFalloffIsTheIrradianceOfTheContinuedSurface) {
    // A plane 2 m away, the fixture's two lamps with their scattered light (lamp fields): the
    // sampled border pixels' factors are the optics' irradiance at the continued point (unscattered
    // plus each field's, in double) over the border pixel's, times the total weights' ratio;
    // those between are linear between them.
    const Camera cam = testing::small_camera();
    const Rig rig = testing::two_lamps();
    const Water w = testing::turbid_water();
    ForwardTransportSettings s;
    s.paths = 1 << 10;
    const ForwardPsf psf(trace_forward_psf(w, forward_psf_depths(8.0, 16), s), w, cam.fx, cam.width,
                         cam.height);
    const float z = 2.0f;
    const Image depth(cam.width, cam.height, 1, z);
    LampFieldSettings ls;
    ls.nr = 10;
    ls.ntheta = 13;
    ls.r0 = 0.05;
    ls.r_max = 12.0;
    ls.samples = 64;  // noise does not matter: both sides read the same table
    std::vector<LampField> fields;
    for (const Light& L : rig.lights) fields.push_back(bake_lamp_field(L, w, ls));
    EdgeFalloff f;
    edge_falloff(cam, depth, AnalyticLamps(rig, w, fields), psf, f);
    ASSERT_EQ(f.width, cam.width);
    ASSERT_GT(f.samples(), 4);
    const Vec3 n(0, 0, -1);
    const auto check = [&](const std::vector<float>& side, int count, int ub, int vb, double du,
                           double dv, bool rows) {
        const int step = edge_falloff_step(count);
        for (int i = 0; i < count; i += step) {
            const double u = rows ? ub : i, v = rows ? i : vb;
            const Vec3 Pb = cam.ray(u, v) * double(z);
            const auto irradiance = [&](const Vec3& P) {
                Rgb e = lamp_irradiance(rig, w, P, n);
                for (int c = 0; c < 3; ++c) e[c] += testing::exact_scattered(rig, fields, P, n, c);
                return e;
            };
            const Rgb eb = irradiance(Pb), tb = psf.total(length(Pb));
            for (int k = 0; k < f.samples(); k += 3) {
                const Vec3 Pq = cam.ray(u + du * f.dist[k], v + dv * f.dist[k]) * double(z);
                const Rgb eq = irradiance(Pq), tq = psf.total(length(Pq));
                for (int c = 0; c < 3; ++c) {
                    const double expect = eq[c] / eb[c] * tq[c] / tb[c];
                    EXPECT_NEAR(f.at(side, i, c, f.dist[k]), expect, 1e-4 + 1e-4 * expect)
                        << "border " << i << " distance " << f.dist[k] << " channel " << c;
                }
            }
        }
    };
    check(f.left, cam.height, 0, 0, -1, 0, true);
    check(f.right, cam.height, cam.width - 1, 0, 1, 0, true);
    check(f.top, cam.width, 0, 0, 0, -1, false);
    check(f.bottom, cam.width, 0, cam.height - 1, 0, 1, false);
    // between samples: linear in the border pixel
    const int K = f.samples();
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < K; ++k) {
            const int step = edge_falloff_step(cam.height);  // samples at step and 2 step
            const float a = f.left[(std::size_t(c) * cam.height + step) * K + k];
            const float b = f.left[(std::size_t(c) * cam.height + 2 * step) * K + k];
            const float t = float(step / 2) / float(step);  // the pixel step + step / 2
            EXPECT_NEAR(f.left[(std::size_t(c) * cam.height + step + step / 2) * K + k],
                        a + t * (b - a), 1e-5f * (a + b));
        }
    }
}

}  // namespace deepsea
