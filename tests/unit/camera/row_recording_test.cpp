// A frame recorded row by row as a renderer hands its rows over (CameraStage::apply_rows) has
// the bits of the same frame recorded whole (apply), whatever the rows' order and threads; the
// meter's histogram counts each pixel's brightest raw DN, and the controller reads the same
// level from it as from the raw layer.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "camera_test_util.h"
#include "deepsea/camera/auto_exposure.h"
#include "deepsea/camera/sensor.h"
#include "deepsea/core/error.h"

namespace deepsea {
namespace {

using namespace camera_test;

/// Bit for bit (NaN payloads and signed zeros included); two empty layers (not asked for) are
/// the same, and memcmp is not called on their null buffers.
bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels &&
           a.data.size() == b.data.size() &&
           (a.data.empty() ||
            std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0);
}

/// Radiance from dark (the Poisson path) to past the full well (clipping).
Image scene(int w, int h, double full) {
    Image img(w, h, 3);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u)
            for (int c = 0; c < 3; ++c)
                img.at(u, v, c) = float(full * 1.3 * (0.001 + double(u) / w) * (1.0 + 0.2 * c) *
                                        (1.0 + 0.5 * std::sin(0.11 * v)));
    return img;
}

/// Hands `radiance`'s rows to `rows` bottom to top from several tasks, each from a buffer
/// offset by one float (never 64-byte aligned), as a compositor's row buffers may be.
void hand_over(const Image& radiance, const CameraStage::RadianceRows& rows) {
    const int h = radiance.height;
    tbb::parallel_for(0, h, [&](int i) {
        const int v = h - 1 - i;
        std::vector<float> buf(3 * std::size_t(radiance.width) + 1);
        std::memcpy(buf.data() + 1, radiance.row(v), 3 * sizeof(float) * radiance.width);
        rows(v, buf.data() + 1);
    });
}

TEST(CameraRows, SameBitsAsTheWholeFrame) {
    CameraModel plain;
    plain.sensor.dark_noise = 1.5;  // the low counts' Poisson path
    CameraModel matrix = plain;     // no display table: the processing kernel per value
    matrix.processing.matrix = std::array<double, 9>{1.2, -0.1, -0.1, -0.1, 1.2, -0.1, 0, 0, 1};
    matrix.sensor.bits = 14;
    for (const CameraModel& m : {plain, matrix}) {
        const Camera cam = pinhole(203, 61, 150.0);  // a width that leaves vector tails
        const CameraStage stage(m, cam);
        ASSERT_TRUE(stage.records_rows());
        const Image radiance = scene(cam.width, cam.height,
                                     m.sensor.full_well / stage.electrons_per_radiance(1, 10.0));
        const FrameExposure e{10.0, 0.3};
        for (const bool codes8 : {false, true}) {
            CameraLayerSet set = CameraLayerSet::all();
            set.codes8 = codes8;
            set.meter = true;
            CameraOutput whole, rows;
            stage.apply(whole, radiance, 7, e, set, Parallel(1));
            stage.apply_rows(
                rows, [&](const CameraStage::RadianceRows& r) { hand_over(radiance, r); }, 7, e,
                set);
            EXPECT_TRUE(same_bits(whole.image, rows.image));
            EXPECT_EQ(whole.codes8, rows.codes8);
            EXPECT_TRUE(same_bits(whole.raw, rows.raw));
            EXPECT_TRUE(same_bits(whole.linear_dn, rows.linear_dn));
            EXPECT_TRUE(same_bits(whole.noise_free, rows.noise_free));
            EXPECT_EQ(whole.brightest, rows.brightest);
            EXPECT_EQ(rows.exposure.system_gain, 0.3);
        }
    }
}

TEST(CameraRows, MeterHistogramCountsTheBrightestRawDn) {
    CameraModel m;
    const Camera cam = pinhole(97, 40, 80.0);
    const CameraStage stage(m, cam);
    const Image radiance =
        scene(cam.width, cam.height, m.sensor.full_well / stage.electrons_per_radiance(1, 10.0));
    // A gain at which the full well reads out past the top DN: the top bin is counted too.
    const double k = 2.0 * max_dn(m.sensor) / m.sensor.full_well;
    CameraLayerSet set;
    set.raw = true;
    set.meter = true;
    CameraOutput out;
    stage.apply(out, radiance, 3, FrameExposure{10.0, k}, set, Parallel(2, 3));
    // An independent count from the raw layer.
    std::vector<std::uint32_t> want(std::size_t(max_dn(m.sensor)) + 1, 0);
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
            const float b =
                std::max(out.raw.at(u, v, 0), std::max(out.raw.at(u, v, 1), out.raw.at(u, v, 2)));
            ++want.at(std::size_t(b));
        }
    EXPECT_EQ(out.brightest, want);
    EXPECT_GT(want.back(), 0u);  // some pixels clip
    // The controller's reading, from the histogram and from the raw layer, both meterings.
    for (const Metering metering : {Metering::Percentile, Metering::Mean}) {
        AutoExposure ae;
        ae.metering = metering;
        const ExposureReading a = meter_exposure(ae, m.sensor, out.brightest, k);
        const ExposureReading b = meter_exposure(ae, m.sensor, out.raw, k);
        EXPECT_EQ(a.level, b.level);
        EXPECT_EQ(a.saturated, b.saturated);
        EXPECT_GT(a.level, 0.0);
    }
    // Without `meter` no histogram; a histogram of another size is refused.
    CameraOutput plain;
    stage.apply(plain, radiance, 3, FrameExposure{10.0, k}, CameraLayerSet{});
    EXPECT_TRUE(plain.brightest.empty());
    EXPECT_THROW(meter_exposure(AutoExposure{}, m.sensor, std::vector<std::uint32_t>(10, 1), k),
                 InputError);
}

TEST(CameraRows, WholeFrameModelsAreRefused) {
    CameraModel lens;
    lens.lens.distortion = {-0.12, 0.02, 0.0, 0.0, 0.0};
    CameraModel grey;
    grey.processing.white_balance = WhiteBalance::GreyWorld;
    CameraModel mosaic;
    mosaic.sensor.bayer = BayerPattern::Rggb;
    const Camera cam = pinhole(64, 48, 60.0);
    for (const CameraModel& m : {lens, grey, mosaic}) {
        const CameraStage stage(m, cam);
        EXPECT_FALSE(stage.records_rows());
        CameraOutput out;
        EXPECT_THROW(stage.apply_rows(
                         out, [](const CameraStage::RadianceRows&) {}, 0, stage.default_exposure()),
                     InputError);
    }
}

}  // namespace
}  // namespace deepsea
