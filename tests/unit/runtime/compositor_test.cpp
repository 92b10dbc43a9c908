#include "deepsea/runtime/compositor.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>

#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/forward_psf.h"
#include "deepsea/reference/reference.h"
#include "deepsea/runtime/asset_backscatter.h"
#include "deepsea/runtime/lamps.h"
#include "runtime_fixtures.h"

namespace deepsea {

namespace {

struct Fixture {
    Camera cam = testing::small_camera();
    Rig rig = testing::two_lamps();
    Water water;
    testing::PlaneScene scene = testing::plane_scene(cam);
    Asset asset;

    explicit Fixture(Water w) : water(std::move(w)) {
        BakeSettings s;
        s.step = 4;  // about the default step of an 800 px image, scaled to 120 px
        asset = bake(cam, rig, water, s);
    }
    /// The exact per-pixel integration, made on first use: each test runs in its own process,
    /// and only the comparisons with it should pay for it.
    const Layers& ref() const {
        std::call_once(ref_once, [this] {
            ReferenceOptions opt;
            opt.open_water_z = asset.lattice().z_max();  // open water ends where the asset does
            opt.quadrature.rel_tol = 1e-6;
            ref_layers = render_reference(cam, rig, water, scene.rgb, scene.depth, opt);
        });
        return ref_layers;
    }
    Layers composite(int threads = 0) const {
        std::unique_ptr<tbb::global_control> limit;
        if (threads > 0) {
            limit = std::make_unique<tbb::global_control>(
                tbb::global_control::max_allowed_parallelism, threads);
        }
        const AnalyticLamps lamps(rig, water);
        const AssetBackscatter bs(asset, cam);
        Compositor comp(cam, water, lamps, bs);
        Layers out;
        comp.composite(out, Frame{scene.rgb, scene.depth});
        return out;
    }

private:
    mutable std::once_flag ref_once;
    mutable Layers ref_layers;
};

/// Jerlov IB with Jaffe-McGlamery forward scatter (the paper's).
const Fixture& fixture() {
    static const Fixture f(testing::ib_with_forward());
    return f;
}

/// Jerlov IB with forward scatter from the phase function.
const Fixture& fixture_psf() {
    static const Fixture f([] {
        Water w = jerlov_water("IB");
        w.forward = phase_function_forward_scatter();
        return w;
    }());
    return f;
}

/// Relative error statistics of layer a vs b over pixels away from depth edges.
struct Stats {
    double mean = 0.0, max = 0.0;
};
Stats compare(const Image& a, const Image& b, const Image& depth, double floor = 1e-12) {
    Stats s;
    long n = 0;
    for (int v = 0; v < a.height; ++v) {
        for (int u = 0; u < a.width; ++u) {
            if (testing::near_edge(depth, u, v)) continue;
            for (int c = 0; c < a.channels; ++c) {
                const double r = b.at(u, v, c);
                const double e = std::fabs(a.at(u, v, c) - r) / std::max(std::fabs(r), floor);
                s.mean += e;
                s.max = std::max(s.max, e);
                ++n;
            }
        }
    }
    s.mean /= std::max(n, 1L);
    return s;
}

}  // namespace

TEST(Compositor, DirectMatchesReference) {
    const Fixture& f = fixture();
    const Layers out = f.composite();
    const Stats s = compare(out.direct, f.ref().direct, f.scene.depth, 1e-9);
    std::printf("direct vs reference: mean %.2e max %.2e\n", s.mean, s.max);
    EXPECT_LE(s.max, 1e-3);
    const Stats t = compare(out.transmission, f.ref().transmission, f.scene.depth, 1e-9);
    EXPECT_LE(t.max, 1e-5);
}

TEST(Compositor, BackscatterLookupMatchesReference) {
    const Fixture& f = fixture();
    const Layers out = f.composite();
    const Stats s = compare(out.backscatter, f.ref().backscatter, f.scene.depth);
    std::printf("backscatter vs reference: mean %.2e max %.2e\n", s.mean, s.max);
    EXPECT_LE(s.mean, 0.005);
    EXPECT_LE(s.max, 0.02);
}

TEST(Compositor, OpenWaterHasBackscatterOnly) {
    const Fixture& f = fixture();
    const Layers out = f.composite();
    const Rgb far = f.asset.sample(f.cam.width - 1, f.cam.height - 1, HUGE_VAL);
    const int u = f.cam.width - 1, v = f.cam.height - 1;  // depth NaN/inf/<=0 there
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(out.direct.at(u, v, c), 0.0f);
        EXPECT_EQ(out.forward.at(u, v, c), 0.0f);
        EXPECT_NEAR(out.backscatter.at(u, v, c), far[c], 1e-6 * far[c]);
        EXPECT_TRUE(std::isfinite(out.final.at(u, v, c)));
    }
    EXPECT_EQ(out.depth.at(u, v), 0.0f);
}

TEST(Compositor, ForwardScatterCloseToExactGather) {
    const Fixture& f = fixture();
    const Layers out = f.composite();
    // The fast blur blends fixed-sigma levels; the reference gathers with each pixel's own
    // Gaussian. Compare away from edges, where the blur reaches across them.
    Image mask = f.scene.depth;
    const Stats s = compare(out.forward, f.ref().forward, mask, 1e-9);
    std::printf("forward vs exact gather: mean %.2e max %.2e\n", s.mean, s.max);
    EXPECT_LE(s.mean, 0.03);
    const Stats fin = compare(out.final, f.ref().final, mask, 1e-9);
    EXPECT_LE(fin.mean, 0.01);
}

TEST(Compositor, PhaseFunctionForwardScatterCloseToExactBlur) {
    // The runtime weighs into box-downsampled images and blurs there; the reference blurs each
    // scale's exactly weighted image at full resolution.
    const Fixture& f = fixture_psf();
    const Layers out = f.composite();
    const Stats s = compare(out.forward, f.ref().forward, f.scene.depth, 1e-9);
    std::printf("forward vs exact blur: mean %.2e max %.2e\n", s.mean, s.max);
    EXPECT_LE(s.mean, 0.03);
    EXPECT_LE(s.max, 0.15);
    const Stats fin = compare(out.final, f.ref().final, f.scene.depth, 1e-9);
    EXPECT_LE(fin.mean, 0.01);
    // Light from the surfaces reaches the open-water pixels beside them too.
    const int u = f.cam.width - 1, v = f.cam.height - 1;
    EXPECT_GT(out.forward.at(u, v, 1), 0.0f);
    EXPECT_EQ(out.direct.at(u, v, 1), 0.0f);
}

TEST(Compositor, FarAndSentinelDepthsAreFiniteAndBounded) {
    // 5e5 m is a (very distant) surface whose blur would be huge; 1e10 and FLT_MAX are "no hit"
    // sentinels. All must composite quickly to finite values, sentinels as open water.
    const Fixture& f = fixture();
    Image depth = f.scene.depth;
    for (int v = 0; v < depth.height; ++v) {
        for (int u = 0; u < depth.width; ++u) {
            if (u % 3 == 0) depth.at(u, v) = 5e5f;
            if (u % 3 == 1 && v % 2 == 0) depth.at(u, v) = 1e10f;
            if (u % 7 == 0 && v % 5 == 0) depth.at(u, v) = std::numeric_limits<float>::max();
        }
    }
    const AnalyticLamps lamps(f.rig, f.water);
    const AssetBackscatter bs(f.asset, f.cam);
    Compositor comp(f.cam, f.water, lamps, bs);
    Layers out;
    comp.composite(out, Frame{f.scene.rgb, depth});
    for (const Image* img : {&out.final, &out.direct, &out.forward, &out.backscatter}) {
        for (float x : img->data) ASSERT_TRUE(std::isfinite(x));
    }
    EXPECT_EQ(out.depth.at(1, 0), 0.0f);      // 1e10: open water
    EXPECT_EQ(out.depth.at(3, 0), 5e5f);      // a surface, however far
    EXPECT_EQ(out.direct.at(3, 1, 1), 0.0f);  // exp(-c 5e5 m) underflows
}

TEST(Compositor, FinalOnlyGivesTheSameImageWithoutTheOtherLayers) {
    const Fixture& f = fixture();
    const Layers all = f.composite();
    const AnalyticLamps lamps(f.rig, f.water);
    const AssetBackscatter bs(f.asset, f.cam);
    Compositor comp(f.cam, f.water, lamps, bs);
    Layers out = all;  // full layers first: Final must free what it does not fill
    comp.composite(out, Frame{f.scene.rgb, f.scene.depth}, LayerSet::Final);
    EXPECT_EQ(out.final.data, all.final.data);
    for (const Image* img : {&out.direct, &out.forward, &out.backscatter, &out.transmission,
                             &out.depth, &out.normal}) {
        EXPECT_TRUE(img->empty());
    }
    comp.composite(out, Frame{f.scene.rgb, f.scene.depth});  // and back to all layers
    EXPECT_EQ(out.forward.data, all.forward.data);
    EXPECT_EQ(out.final.data, all.final.data);
    // With the phase function's point spread the image alone takes D from the spread's table
    // (a bounded approximation, approximations_test.cpp); the exact path gives the same bits.
    const Fixture& p = fixture_psf();
    const AnalyticLamps psf_lamps(p.rig, p.water);
    const AssetBackscatter psf_bs(p.asset, p.cam);
    Compositor exact(p.cam, p.water, psf_lamps, psf_bs);
    exact.set_exact(true);
    Layers every, alone;
    exact.composite(every, Frame{p.scene.rgb, p.scene.depth});
    exact.composite(alone, Frame{p.scene.rgb, p.scene.depth}, LayerSet::Final);
    EXPECT_EQ(alone.final.data, every.final.data);
}

TEST(Compositor, RowsHandedOverAreTheFinalImageWhateverTheForwardScatter) {
    // A sequence encodes each row as it is finished: every row once, the final layer's values
    // bit for bit; nothing of the image is kept, with forward scatter or without.
    for (const Fixture* f : {&fixture(), &fixture_psf()}) {
        for (const bool forward : {true, false}) {
            Water water = f->water;
            water.forward.enabled = forward;
            const AnalyticLamps lamps(f->rig, water);
            const AssetBackscatter bs(f->asset, f->cam);
            Compositor comp(f->cam, water, lamps, bs);
            const Frame frame{f->scene.rgb, f->scene.depth};
            Layers kept;
            comp.composite(kept, frame, LayerSet::Final);
            const int W = f->cam.width, H = f->cam.height;
            Image rows(W, H, 3);
            std::vector<std::atomic<int>> seen(H);
            Layers scratch = kept;
            comp.composite(scratch, frame, [&](int v, const float* rgb) {
                ASSERT_TRUE(v >= 0 && v < H);
                seen[v]++;
                std::copy(rgb, rgb + 3 * W, rows.row(v));
            });
            for (int v = 0; v < H; ++v) ASSERT_EQ(seen[v].load(), 1) << "row " << v;
            EXPECT_EQ(rows.data, kept.final.data) << (forward ? "forward" : "no forward");
            EXPECT_TRUE(scratch.final.empty());
        }
    }
}

TEST(Compositor, ColourGivenAsSrgbCodesGivesTheSameImageAsItsFloatDecode) {
    // A sequence hands PNG and JPEG colour over as codes, decoded a row at a time; the pixels
    // must be those of the whole image decoded first (read_color), in 8 and 16 bits.
    const Fixture& f = fixture_psf();
    const AnalyticLamps lamps(f.rig, f.water);
    const AssetBackscatter bs(f.asset, f.cam);
    Compositor comp(f.cam, f.water, lamps, bs);
    const std::size_t n = f.scene.rgb.data.size();
    for (const int bits : {8, 16}) {
        Frame coded(Image(), f.scene.depth);
        coded.codes.width = f.cam.width;
        coded.codes.height = f.cam.height;
        coded.codes.bits = bits;
        Image decoded(f.cam.width, f.cam.height, 3);
        if (bits == 8) {
            coded.codes.rgb8.resize(n);
            for (std::size_t i = 0; i < n; ++i) coded.codes.rgb8[i] = std::uint8_t((i * 37) % 256);
            srgb_decode(coded.codes.rgb8.data(), n, decoded.data.data());
        } else {
            coded.codes.rgb16.resize(n);
            for (std::size_t i = 0; i < n; ++i) coded.codes.rgb16[i] = std::uint16_t(i * 997);
            srgb_decode(coded.codes.rgb16.data(), n, decoded.data.data());
        }
        ASSERT_TRUE(coded.coded());
        Layers from_codes, from_float;
        comp.composite(from_codes, coded);
        comp.composite(from_float, Frame{decoded, f.scene.depth});
        EXPECT_EQ(from_codes.final.data, from_float.final.data) << bits << " bits";
        EXPECT_EQ(from_codes.direct.data, from_float.direct.data) << bits << " bits";

        // codes that do not fill the frame are refused, not read beyond
        Frame short_codes = coded;
        if (bits == 8) {
            short_codes.codes.rgb8.pop_back();
        } else {
            short_codes.codes.rgb16.pop_back();
        }
        EXPECT_THROW(comp.composite(from_codes, short_codes), InputError);
    }
}

TEST(Compositor, IdenticalAtAnyThreadCount) {
    const Fixture& f = fixture();
    const Layers one = f.composite(1);
    const Layers two = f.composite(2);
    EXPECT_EQ(one.final.data, two.final.data);
    EXPECT_EQ(one.forward.data, two.forward.data);
}

TEST(Compositor, RefusesMismatchedFrames) {
    const Fixture& f = fixture();
    const AnalyticLamps lamps(f.rig, f.water);
    const AssetBackscatter bs(f.asset, f.cam);
    Compositor comp(f.cam, f.water, lamps, bs);
    Layers out;
    EXPECT_THROW(comp.composite(out, Frame{f.scene.rgb, Image(10, 10, 1)}), InputError);
    EXPECT_THROW(comp.composite(out, Frame{Image(10, 10, 3), Image(10, 10, 1)}), InputError);
}

TEST(AssetBackscatter, RefusesAnotherCamera) {
    const Fixture& f = fixture();
    Camera other = f.cam;
    other.fx *= 1.2;
    EXPECT_THROW(AssetBackscatter(f.asset, other), AssetError);
}

TEST(AssetBackscatter, EveryPixelOfARowIsTheAssetsOwnSample) {
    // Depths on every kind of place: open water (0, which looks up z_max), beyond z_max, on
    // and between the depth samples, near the camera; 117 of the 120 pixels, so that the vector
    // path's groups of 8 and the scalar rest both run. Asset::sample (double) is the reference.
    const Fixture& f = fixture();
    const AssetBackscatter bs(f.asset, f.cam);
    const Lattice& l = f.asset.lattice();
    const int n = 117, v = 41;
    std::vector<float> z(n), out(3 * n);
    for (int u = 0; u < n; ++u) {
        const int k = u % int(l.z.size());
        z[u] = u % 11 == 0  ? 0.0f
               : u % 7 == 0 ? float(l.z_max() * 1.5)
               : u % 3 == 0 ? float(l.z[k])
                            : float(0.05 + (l.z_max() - 0.05) * ((u * 37) % 101) / 100.0);
    }
    bs.backscatter_row(v, n, z.data(), out.data());
    for (int u = 0; u < n; ++u) {
        const Rgb ref = f.asset.sample(u, v, z[u] > 0.0f ? double(z[u]) : HUGE_VAL);
        for (int c = 0; c < 3; ++c) {
            ASSERT_NEAR(out[3 * u + c], ref[c], 1e-5 * ref[c] + 1e-12)
                << "pixel " << u << ", z " << z[u];
        }
    }
}

TEST(AssetBackscatter, ResamplesTheSameViewAtAnotherResolution) {
    const Fixture& f = fixture();
    Camera half = f.cam;  // 80x60, the same rays at pixel centres
    half.width /= 2;
    half.height /= 2;
    half.fx /= 2;
    half.fy /= 2;
    half.cx = (f.cam.cx + 0.5) / 2 - 0.5;
    half.cy = (f.cam.cy + 0.5) / 2 - 0.5;
    const AssetBackscatter bs(f.asset, half);
    std::vector<float> z(half.width, 4.0f), out(3 * half.width);
    bs.backscatter_row(17, half.width, z.data(), out.data());
    for (int u : {0, 13, 40, half.width - 1}) {
        // pixel (u, 17) of the half camera is image point (2u + 0.5, 34.5) of the asset camera
        const Rgb ref = f.asset.sample(2 * u + 0.5, 2 * 17 + 0.5, 4.0);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[3 * u + c], ref[c], 1e-5 * ref[c]);
    }
}

}  // namespace deepsea

namespace deepsea {

TEST(Compositor, ForwardScatterIsAttenuatedOnce) {
    // A flat, uniformly grey plane facing the camera at 3 m in Jerlov 3C water. Light scattered
    // within the small forward cone is not lost from the image: direct + forward decay together
    // as exp(-G d), G = c - f b, so F / D = w / T = exp((c - G) d) - 1 at the image centre (the
    // lamp light varies slowly there against the blur). Blurring D, which already carries
    // exp(-c d), gave 0.15 here instead of about 1.6.
    const Camera cam = testing::small_camera();
    Water water = jerlov_water("3C");
    water.forward = default_forward_scatter(water);
    water.forward.enabled = true;
    const double d = 3.0;
    Frame frame{Image(cam.width, cam.height, 3, 0.5f), Image(cam.width, cam.height, 1, float(d))};
    const Asset asset = bake(cam, testing::two_lamps(), water, BakeSettings{});
    const AnalyticLamps lamps(testing::two_lamps(), water);
    const AssetBackscatter backscatter(asset, cam);
    Compositor comp(cam, water, lamps, backscatter);
    Layers out;
    comp.composite(out, frame);
    const int u = cam.width / 2, v = cam.height / 2;
    const double d2 = length(cam.ray(u, v) * d);
    for (int c = 0; c < 3; ++c) {
        const double expect = std::exp((water.c[c] - water.forward.G[c]) * d2) - 1.0;
        const double got = out.forward.at(u, v, c) / out.direct.at(u, v, c);
        std::printf("channel %d: F / D = %.3f, exp((c - G) d) - 1 = %.3f\n", c, got, expect);
        EXPECT_NEAR(got, expect, 0.03 * expect);
    }
}

}  // namespace deepsea

namespace deepsea {

namespace {

/// The frame's grid of scattered-light coefficients (begin_frame), interpolated in both
/// directions, exact across depth edges (the box) and never on open water: the direct layer's
/// scattered part against the per-pixel definition, every pixel. Returns the worst error.
double grid_error(const Camera& cam, const Rig& rig, const Water& water) {
    const testing::PlaneScene scene = testing::plane_scene(cam);
    const Asset asset = bake(cam, rig, water, BakeSettings{});
    const std::vector<LampField> fields(rig.lights.size(), testing::smooth_lamp_field());
    const AssetBackscatter bs(asset, cam);
    const Frame frame{scene.rgb, scene.depth};
    Layers plain, all;
    const AnalyticLamps unscattered(rig, water), lamps(rig, water, fields);
    Compositor(cam, water, unscattered, bs).composite(plain, frame);
    Compositor(cam, water, lamps, bs).composite(all, frame);
    double worst = 0.0;
    long open_water = 0;
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const float z = all.depth.at(u, v);
            if (!(z > 0.0f)) {
                ++open_water;
                for (int c = 0; c < 3; ++c) EXPECT_EQ(all.direct.at(u, v, c), 0.0f);
                continue;
            }
            const Vec3 P = cam.ray(u, v) * double(z);
            const Vec3 N(all.normal.at(u, v, 0), all.normal.at(u, v, 1), all.normal.at(u, v, 2));
            for (int c = 0; c < 3; ++c) {
                const double expect = scene.rgb.at(u, v, c) / M_PI *
                                      testing::exact_scattered(rig, fields, P, N, c) *
                                      all.transmission.at(u, v, c);
                const double got = all.direct.at(u, v, c) - plain.direct.at(u, v, c);
                worst = std::max(worst, std::fabs(got - expect) / expect);
            }
        }
    }
    EXPECT_GT(open_water, 0);
    return worst;
}

}  // namespace

TEST(Compositor, ScatteredLampLightOnTheFrameGridMatchesExact) {
    // A wide small camera (fx = 90: points at every pixel) and a narrow one (fx = 600: every
    // 8th pixel, the demo camera's spacing): within 1 % everywhere.
    const Camera narrow{240, 180, 600.0, 600.0, 119.5, 89.5};
    for (const Camera& cam : {testing::small_camera(), narrow}) {
        const double worst = grid_error(cam, testing::two_lamps(), testing::ib_with_forward());
        std::printf("scattered light on the frame grid, fx %.0f: worst relative error %.2e\n",
                    cam.fx, worst);
        EXPECT_LT(worst, 1e-2);
    }
}

}  // namespace deepsea
