// Image messages as frame views (live/image_message.h): every colour encoding renders the same
// image as rgb8 of the same codes, 16UC1 millimetres the same as 32FC1 metres (0 = open water
// as NaN), and each malformed message is refused with a line naming the topic and the reason.

#include "deepsea/live/image_message.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/runtime/renderer.h"
#include "live_fixtures.h"

namespace deepsea {

namespace {

using testing::Rgbd;

Image render(const ColorView& c, const DepthView& d) {
    Renderer r(testing::live_asset());
    Layers out;
    r.render(out, c, d, LayerSet::Final);
    return out.final;
}

ImageMessage msg(const std::string& enc, int w, int h, std::size_t step,
                 const std::vector<std::uint8_t>& bytes, const char* topic = "camera/image_raw") {
    ImageMessage m;
    m.encoding = enc;
    m.width = std::uint32_t(w);
    m.height = std::uint32_t(h);
    m.step = std::uint32_t(step);
    m.data = bytes.data();
    m.size = bytes.size();
    m.topic = topic;
    return m;
}

std::string refusal(const ImageMessage& m, bool depth = false) {
    try {
        if (depth)
            (void)depth_view(m);
        else
            (void)color_view(m);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(ImageMessage, EveryColourLayoutRendersAsRgb8) {
    const Rgbd f = testing::live_frame(120, 90);
    const int w = f.width, h = f.height;
    const ImageMessage depth = msg("32FC1", w, h, 4 * w, f.depth32, "depth");
    const DepthView dv = depth_view(depth);
    const Image want = render(color_view(msg("rgb8", w, h, 3 * w, f.rgb8)), dv);
    // bgr8 with a padded step, rgba8 and bgra8 (alpha ignored), rgb16 (c * 257: the same
    // sRGB value)
    const std::size_t pad = 3 * w + 5;
    std::vector<std::uint8_t> bgr(pad * h, 0xEE), rgba(4 * w * h), bgra(4 * w * h);
    std::vector<std::uint8_t> rgb16(6 * w * h);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u)
            for (int c = 0; c < 3; ++c) {
                const std::uint8_t x = f.rgb8[(v * w + u) * 3 + c];
                bgr[v * pad + u * 3 + (2 - c)] = x;
                rgba[(v * w + u) * 4 + c] = x;
                bgra[(v * w + u) * 4 + (2 - c)] = x;
                const std::uint16_t y = std::uint16_t(x * 257);
                std::memcpy(&rgb16[((v * w + u) * 3 + c) * 2], &y, 2);
            }
    for (std::size_t i = 3; i < rgba.size(); i += 4) rgba[i] = bgra[i] = std::uint8_t(i);
    const std::pair<ImageMessage, float> cases[] = {{msg("bgr8", w, h, pad, bgr), 0.0f},
                                                    {msg("rgba8", w, h, 4 * w, rgba), 0.0f},
                                                    {msg("bgra8", w, h, 4 * w, bgra), 0.0f},
                                                    {msg("rgb16", w, h, 6 * w, rgb16), 1e-5f}};
    for (const auto& [m, tol] : cases) {
        const Image got = render(color_view(m), dv);
        ASSERT_EQ(got.data.size(), want.data.size()) << m.encoding;
        for (std::size_t i = 0; i < got.data.size(); ++i)
            ASSERT_NEAR(got.data[i], want.data[i], tol * std::fabs(want.data[i]) + 1e-12f)
                << m.encoding << " sample " << i;
    }
}

TEST(ImageMessage, MillimetreDepthIsMetreDepthAndZeroIsOpenWater) {
    const Rgbd f = testing::live_frame(120, 90);
    const int w = f.width, h = f.height;
    std::vector<std::uint8_t> mm(2 * w * h), metres(4 * w * h);
    for (int i = 0; i < w * h; ++i) {
        float z;
        std::memcpy(&z, &f.depth32[4 * i], 4);
        // whole millimetres, and a block of "no reading" (0) against NaN
        const bool hole = (i % w) < 10 && (i / w) < 10;
        const std::uint16_t units = hole ? 0 : std::uint16_t(std::lround(z * 1000.0f));
        std::memcpy(&mm[2 * i], &units, 2);
        const float back = hole ? std::numeric_limits<float>::quiet_NaN() : units * 0.001f;
        std::memcpy(&metres[4 * i], &back, 4);
    }
    const ColorView cv = color_view(msg("rgb8", w, h, 3 * w, f.rgb8));
    const Image a = render(cv, depth_view(msg("16UC1", w, h, 2 * w, mm, "depth")));
    const Image b = render(cv, depth_view(msg("32FC1", w, h, 4 * w, metres, "depth")));
    ASSERT_EQ(a.data.size(), b.data.size());
    for (std::size_t i = 0; i < a.data.size(); ++i)
        ASSERT_NEAR(a.data[i], b.data[i], 1e-5f * std::fabs(b.data[i]) + 1e-12f) << i;
}

TEST(ImageMessage, MalformedMessagesAreRefusedWithTheirReason) {
    const std::vector<std::uint8_t> bytes(3 * 8 * 4, 0);
    const auto has = [](const std::string& what, const std::string& part) {
        return what.find(part) != std::string::npos;
    };
    std::string e = refusal(msg("mono8", 8, 4, 8, bytes));
    EXPECT_TRUE(has(e, "camera/image_raw: encoding 'mono8'")) << e;
    e = refusal(msg("rgb8", 8, 4, 24, {}));
    EXPECT_TRUE(has(e, "camera/image_raw: empty image")) << e;
    e = refusal(msg("rgb8", 0, 4, 24, bytes));
    EXPECT_TRUE(has(e, "empty image")) << e;
    e = refusal(msg("rgb8", 8, 4, 20, bytes));
    EXPECT_TRUE(has(e, "step 20 is shorter than a row")) << e;
    e = refusal(msg("rgb8", 8, 5, 24, bytes));
    EXPECT_TRUE(has(e, "data holds 96 bytes, step x height is 120")) << e;
    ImageMessage big = msg("rgb16", 4, 4, 24, bytes);
    big.big_endian = true;
    EXPECT_TRUE(has(refusal(big), "big-endian")) << refusal(big);
    e = refusal(msg("rgb8", 8, 4, 24, bytes, "depth"), true);
    EXPECT_TRUE(has(e, "depth: encoding 'rgb8' is not a depth encoding")) << e;
    e = refusal(msg("32FC1", 5, 4, 22, std::vector<std::uint8_t>(88), "depth"), true);
    EXPECT_TRUE(has(e, "not a whole number of 4-byte samples")) << e;
    // a valid message is taken
    EXPECT_EQ(refusal(msg("rgb8", 8, 4, 24, bytes)), "");
}

TEST(ImageMessage, SizeMismatchBetweenColourAndDepthNamesBoth) {
    const std::vector<std::uint8_t> c(3 * 8 * 4), d(4 * 6 * 4);
    const ColorView cv = color_view(msg("rgb8", 8, 4, 24, c, "rgb"));
    const DepthView dv = depth_view(msg("32FC1", 6, 4, 24, d, "depth"));
    try {
        check_same_size(cv, dv);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "rgb is 8x4 but depth is 6x4");
    }
    EXPECT_NO_THROW(check_same_size(
        cv, depth_view(msg("32FC1", 8, 4, 32, std::vector<std::uint8_t>(128), "d"))));
}

}  // namespace deepsea
