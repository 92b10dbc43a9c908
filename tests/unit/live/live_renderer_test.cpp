// LiveRenderer (live/live_renderer.h): its image is the renderer's final layer exposed and
// sRGB-encoded (computed here through Renderer and colour's encoder), the automatic exposure
// is the first frame's and kept, a change of size remakes the per-size state, a frame the
// asset cannot take is refused and leaves the output as it was; intrinsics checks and the
// once-per-change reporter.

#include "deepsea/live/live_renderer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "deepsea/colour/srgb.h"
#include "deepsea/core/error.h"
#include "deepsea/live/image_message.h"
#include "live_fixtures.h"

namespace deepsea {

namespace {

struct Views {
    ImageMessage c, d;
    ColorView color() const { return color_view(c); }
    DepthView depth() const { return depth_view(d); }
};

Views views(const testing::Rgbd& f) {
    Views v;
    v.c.encoding = "rgb8";
    v.d.encoding = "32FC1";
    for (ImageMessage* m : {&v.c, &v.d}) {
        m->width = std::uint32_t(f.width);
        m->height = std::uint32_t(f.height);
    }
    v.c.step = std::uint32_t(3 * f.width);
    v.c.data = f.rgb8.data();
    v.c.size = f.rgb8.size();
    v.d.step = std::uint32_t(4 * f.width);
    v.d.data = f.depth32.data();
    v.d.size = f.depth32.size();
    v.d.topic = "depth";
    return v;
}

/// The renderer's final layer for the frame, and its codes at `exposure` (0: the automatic
/// exposure of that final layer).
std::vector<std::uint8_t> expected_codes(const testing::Rgbd& f, double exposure) {
    Renderer r(testing::live_asset());
    Layers out;
    const Views v = views(f);
    r.render(out, v.color(), v.depth(), LayerSet::Final);
    if (exposure == 0.0) exposure = exposure_factor(Exposure{}, out.final);
    std::vector<std::uint8_t> codes(out.final.data.size());
    srgb_encode(out.final.data.data(), codes.size(), exposure, codes.data());
    return codes;
}

}  // namespace

TEST(LiveRenderer, ImageIsTheExposedFinalLayerAndTheExposureIsKept) {
    LiveSettings s;
    s.depth = true;
    s.backscatter = true;
    LiveRenderer live(testing::live_asset(), s);
    const testing::Rgbd first = testing::live_frame(120, 90),
                        dim = testing::live_frame(120, 90, 0.3f);
    LiveFrame out;
    Views v = views(first);
    live.render(out, v.color(), v.depth(), 1);
    EXPECT_EQ(out.image, expected_codes(first, 0.0));
    const double chosen = live.exposure();
    EXPECT_GT(chosen, 0.0);
    EXPECT_EQ(out.exposure, chosen);
    // a darker second frame keeps the first frame's exposure (its own would be higher)
    v = views(dim);
    live.render(out, v.color(), v.depth(), 2);
    EXPECT_EQ(live.exposure(), chosen);
    EXPECT_EQ(out.image, expected_codes(dim, chosen));
    EXPECT_NE(out.image, expected_codes(dim, 0.0));
    // layers: depth as given (every pixel a surface), backscatter brighter than nothing
    ASSERT_EQ(out.depth.size(), std::size_t(120 * 90));
    for (int i = 0; i < 120 * 90; ++i) {
        float z;
        std::memcpy(&z, &dim.depth32[4 * i], 4);
        ASSERT_FLOAT_EQ(out.depth[i], z) << i;
    }
    ASSERT_EQ(out.backscatter.size(), out.image.size());
    EXPECT_GT(out.backscatter[3 * (45 * 120 + 60) + 2], 0);
}

TEST(LiveRenderer, ANewSizeRemakesTheStateAndABadOneLeavesTheOutput) {
    LiveSettings s;
    s.exposure.automatic = false;
    s.exposure.factor = 30.0;
    LiveRenderer live(testing::live_asset(), s);
    LiveFrame out;
    const testing::Rgbd big = testing::live_frame(120, 90), half = testing::live_frame(60, 45);
    Views v = views(big);
    live.render(out, v.color(), v.depth(), 1);
    EXPECT_EQ(live.sizes_seen(), 1);
    live.render(out, v.color(), v.depth(), 2);
    EXPECT_EQ(live.sizes_seen(), 1);
    v = views(half);
    live.render(out, v.color(), v.depth(), 3);
    EXPECT_EQ(live.sizes_seen(), 2);
    EXPECT_EQ(out.width, 60);
    EXPECT_EQ(out.height, 45);
    EXPECT_DOUBLE_EQ(out.camera.fx, 45.0);  // the asset's camera at half size
    EXPECT_EQ(out.image, expected_codes(half, 30.0));
    // another aspect ratio: the asset's camera cannot take it; the output stays
    const testing::Rgbd square = testing::live_frame(90, 90);
    const std::vector<std::uint8_t> before = out.image;
    v = views(square);
    EXPECT_THROW(live.render(out, v.color(), v.depth(), 4), AssetError);
    EXPECT_EQ(out.image, before);
    EXPECT_EQ(out.width, 60);
}

TEST(LiveRenderer, SettingsThatCannotWorkAreRefused) {
    LiveSettings s;
    s.noise_free = true;
    EXPECT_THROW(LiveRenderer(testing::live_asset(), s), ConfigError);
    s.noise_free = false;
    s.camera_model = CameraModel{};
    s.backscatter = true;
    EXPECT_THROW(LiveRenderer(testing::live_asset(), s), ConfigError);
}

TEST(Intrinsics, MismatchNamesTheValueAndSizes) {
    const Camera c = testing::live_camera();
    EXPECT_EQ(intrinsics_mismatch(c, c), "");
    Camera g = c;
    g.fx += 0.05;  // within 1e-3 of 90 px
    EXPECT_EQ(intrinsics_mismatch(c, g), "");
    g.fx = 100.0;
    const std::string e = intrinsics_mismatch(c, g);
    EXPECT_NE(e.find("camera_info fx 100 differs from the asset camera's 90"), std::string::npos)
        << e;
    g = c;
    g.width = 64;
    EXPECT_NE(intrinsics_mismatch(c, g).find("camera_info is 64x90 but the frames are 120x90"),
              std::string::npos);
}

TEST(ChangeReporter, ReportsOncePerChange) {
    ChangeReporter r;
    EXPECT_TRUE(r.report("a"));
    EXPECT_FALSE(r.report("a"));
    EXPECT_TRUE(r.report("b"));
    EXPECT_FALSE(r.report(""));  // all well: nothing to say, and resets
    EXPECT_TRUE(r.report("b"));
}

}  // namespace deepsea
