// Frames in the caller's memory (runtime/frame_view.h): every layout a view can describe renders
// the same bits as the owned frame io would read from files, and a view that does not describe
// its memory is refused with a line naming it.

#include "deepsea/runtime/frame_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/normals.h"
#include "deepsea/runtime/renderer.h"
#include "runtime_fixtures.h"

namespace deepsea {

namespace {

const Asset& small_asset() {
    static const Asset asset = [] {
        BakeSettings s;
        s.step = 8;
        s.depth_samples = 8;
        return bake(testing::small_camera(), testing::two_lamps(), testing::ib_with_forward(), s);
    }();
    return asset;
}

void expect_same_bits(const Layers& a, const Layers& b) {
    for (const auto& [x, y] :
         {std::pair{&a.final, &b.final}, std::pair{&a.direct, &b.direct},
          std::pair{&a.forward, &b.forward}, std::pair{&a.backscatter, &b.backscatter},
          std::pair{&a.depth, &b.depth}, std::pair{&a.normal, &b.normal}}) {
        ASSERT_EQ(x->data.size(), y->data.size());
        for (std::size_t i = 0; i < x->data.size(); ++i) {
            const float p = x->data[i], q = y->data[i];
            ASSERT_TRUE(p == q || (std::isnan(p) && std::isnan(q))) << "sample " << i;
        }
    }
}

/// sRGB codes of a linear image, 8 or 16 bits, interleaved RGB.
template <class T>
std::vector<T> codes(const Image& rgb, int max) {
    std::vector<T> out(rgb.data.size());
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = T(std::lround(linear_to_srgb(rgb.data[i]) * float(max)));
    return out;
}

/// The owned frame of `codes` as read_frame_color holds a PNG's.
Frame coded_frame(const std::vector<std::uint8_t>& rgb8, const Image& depth) {
    Frame f;
    f.codes.width = depth.width;
    f.codes.height = depth.height;
    f.codes.rgb8 = rgb8;
    f.depth = depth;
    return f;
}

void expect_refused(const ColorView& c, const DepthView& d, const std::string& words) {
    Renderer r(small_asset());
    Layers out;
    try {
        r.render(out, c, d);
        FAIL() << "accepted; expected: " << words;
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(FrameView, PackedFloatViewsRenderTheOwnedFramesBits) {
    const Camera cam = testing::small_camera();
    const testing::PlaneScene s = testing::plane_scene(cam);
    Renderer by_frame(small_asset()), by_view(small_asset());
    Frame frame{s.rgb, s.depth};
    Layers a, b;
    by_frame.render(a, frame);
    ColorView c{s.rgb.data.data(), cam.width, cam.height, SampleType::F32, ColorEncoding::Linear};
    DepthView d{s.depth.data.data(), cam.width, cam.height};
    by_view.render(b, c, d);
    expect_same_bits(a, b);
}

TEST(FrameView, StridedBgraCodesAndPaddedMillimetresRenderAsFiles) {
    // OpenCV's BGRA 8-bit colour in rows padded to 512 bytes; ROS 16UC1 millimetres with a
    // pixel stride of two samples (every other one skipped).
    const Camera cam = testing::small_camera();
    const int W = cam.width, H = cam.height;
    const testing::PlaneScene s = testing::plane_scene(cam);
    const std::vector<std::uint8_t> rgb8 = codes<std::uint8_t>(s.rgb, 255);
    std::vector<std::uint8_t> bgra(std::size_t(512) * H, 7);
    std::vector<std::uint16_t> mm(std::size_t(2) * W * H, 9);
    Image metres(W, H, 1);
    for (int v = 0; v < H; ++v) {
        for (int u = 0; u < W; ++u) {
            const std::size_t i = std::size_t(v) * W + u;
            for (int k = 0; k < 3; ++k)
                bgra[std::size_t(v) * 512 + 4 * u + (2 - k)] = rgb8[3 * i + k];
            const float z = s.depth.at(u, v);
            const std::uint16_t units = has_surface(z) ? std::uint16_t(std::lround(z * 1000)) : 0;
            mm[2 * i] = units;
            metres.at(u, v) = float(double(units) * 0.001);  // as io reads 16-bit depth
        }
    }
    ColorView c{bgra.data(), W, H, SampleType::U8, ColorEncoding::Srgb, ChannelOrder::Bgr, 4, 512};
    DepthView d{mm.data(), W, H, SampleType::U16, DepthKind::Z, 0.001, 4};
    Renderer by_view(small_asset()), by_frame(small_asset());
    Layers a, b;
    by_view.render(a, c, d);
    Frame f = coded_frame(rgb8, metres);
    by_frame.render(b, f);
    expect_same_bits(a, b);
}

TEST(FrameView, SixteenBitCodesRangeDepthAndImageRows) {
    const Camera cam = testing::small_camera();
    const testing::PlaneScene s = testing::plane_scene(cam);
    std::vector<std::uint16_t> rgb16 = codes<std::uint16_t>(s.rgb, 65535);
    // range depth: the view's is made planar in the renderer's copy, the frame's in place
    Image range = s.depth;
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            float& z = range.at(u, v);
            if (has_surface(z)) z = float(z / cam.cos_phi(u, v));
        }
    }
    const Image range_copy = range;
    ColorView c{rgb16.data(), cam.width, cam.height, SampleType::U16};
    DepthView d{range.data.data(), cam.width, cam.height, SampleType::F32, DepthKind::Range};
    Renderer by_view(small_asset()), by_frame(small_asset());
    Layers a, b;
    std::vector<float> rows(std::size_t(3) * cam.width * cam.height);
    by_view.render(a, c, d, [&](int v, const float* rgb) {
        std::copy(rgb, rgb + 3 * cam.width, rows.begin() + std::ptrdiff_t(3) * cam.width * v);
    });
    EXPECT_EQ(std::memcmp(range.data.data(), range_copy.data.data(), 4 * range.data.size()), 0)
        << "the caller's depth was written to";
    Frame f;
    f.codes.width = cam.width;
    f.codes.height = cam.height;
    f.codes.bits = 16;
    f.codes.rgb16 = rgb16;
    f.depth = range;
    by_frame.render(b, f, LayerSet::Final, DepthKind::Range);
    ASSERT_EQ(rows.size(), b.final.data.size());
    for (std::size_t i = 0; i < rows.size(); ++i) ASSERT_EQ(rows[i], b.final.data[i]) << i;
}

TEST(FrameView, LinearIntegerAndSrgbFloatColourDecode) {
    const Camera cam = testing::small_camera();
    const testing::PlaneScene s = testing::plane_scene(cam);
    // linear 16-bit: x / 65535; sRGB float: the curve on each value
    std::vector<std::uint16_t> lin16(s.rgb.data.size());
    Image as_float(cam.width, cam.height, 3), srgb_float(cam.width, cam.height, 3);
    for (std::size_t i = 0; i < lin16.size(); ++i) {
        lin16[i] = std::uint16_t(std::lround(s.rgb.data[i] * 65535.0f));
        as_float.data[i] = float(lin16[i]) / 65535.0f;
        srgb_float.data[i] = linear_to_srgb(s.rgb.data[i]);
    }
    DepthView d{s.depth.data.data(), cam.width, cam.height};
    Renderer r(small_asset());
    Layers a, b, c2, e;
    r.render(a,
             ColorView{lin16.data(), cam.width, cam.height, SampleType::U16, ColorEncoding::Linear},
             d);
    r.render(b,
             ColorView{as_float.data.data(), cam.width, cam.height, SampleType::F32,
                       ColorEncoding::Linear},
             d);
    expect_same_bits(a, b);
    Image decoded = srgb_float;
    for (float& x : decoded.data) x = srgb_to_linear(x);
    r.render(c2,
             ColorView{srgb_float.data.data(), cam.width, cam.height, SampleType::F32,
                       ColorEncoding::Srgb},
             d);
    r.render(e,
             ColorView{decoded.data.data(), cam.width, cam.height, SampleType::F32,
                       ColorEncoding::Linear},
             d);
    expect_same_bits(c2, e);
}

TEST(FrameView, ViewsThatDoNotDescribeTheirMemoryAreRefused) {
    const Camera cam = testing::small_camera();
    const int W = cam.width, H = cam.height;
    std::vector<float> rgb(std::size_t(3) * W * H + 1, 0.5f), z(std::size_t(W) * H + 1, 2.0f);
    const ColorView c{rgb.data(), W, H, SampleType::F32, ColorEncoding::Linear};
    const DepthView d{z.data(), W, H};

    ColorView bad = c;
    bad.data = nullptr;
    expect_refused(bad, d, "colour view: no data");
    bad = c;
    bad.pixel_stride = 8;
    expect_refused(bad, d, "colour view: pixel stride 8 bytes is less than a pixel's 12");
    bad = c;
    bad.row_stride = 12 * W - 4;
    expect_refused(bad, d, "colour view: row stride");
    bad = c;
    bad.data = reinterpret_cast<const char*>(rgb.data()) + 1;
    expect_refused(bad, d, "multiples of the sample size");
    bad = c;
    bad.width = 0;
    expect_refused(bad, d, "colour view: image size 0x90 has no pixels");
    bad = c;
    bad.width = W - 1;
    expect_refused(bad, d, "sizes differ");

    DepthView badd = d;
    badd.type = SampleType::U8;
    expect_refused(c, badd, "depth view: 8-bit depth is refused");
    badd = d;
    badd.type = SampleType::U16;
    badd.scale = std::numeric_limits<double>::quiet_NaN();
    expect_refused(c, badd, "depth view: depth scale");
    badd = d;
    badd.height = 100'001;
    expect_refused(c, badd, "depth view: image size");

    // Float colour is albedo: a NaN is named by its pixel, whatever the layout.
    rgb[3 * (std::size_t(5) * W + 7) + 1] = std::numeric_limits<float>::quiet_NaN();
    expect_refused(c, d, "colour view: pixel (7, 5) G is NaN");
}

}  // namespace deepsea

namespace deepsea {

TEST(FrameView, AMadeCompositorRendersTheBitsOfOneMadeAtTheFrame) {
    // render_sequence makes the compositor while the first frames are read (prepare): made
    // ahead for the frame's size, or for another size first, the frame's bits are the same.
    const Camera cam = testing::small_camera();
    const testing::PlaneScene s = testing::plane_scene(cam);
    Renderer at_frame(small_asset()), ahead(small_asset()), resized(small_asset());
    ahead.prepare(cam.width, cam.height);
    EXPECT_EQ(ahead.camera().width, cam.width);
    resized.prepare(2 * cam.width, 2 * cam.height);
    Frame f1{s.rgb, s.depth}, f2{s.rgb, s.depth}, f3{s.rgb, s.depth};
    Layers a, b, c;
    at_frame.render(a, f1);
    ahead.render(b, f2);
    resized.render(c, f3);
    expect_same_bits(a, b);
    expect_same_bits(a, c);
    // a size the asset cannot take: the same error a frame of that size meets
    EXPECT_THROW(Renderer(small_asset()).prepare(cam.width, cam.width), AssetError);
}

}  // namespace deepsea
