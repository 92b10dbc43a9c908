// A frame's noise is a function of (seed, frame key, pixel) only: the same bits whatever the
// order of frames and the thread count; frames differ in their temporal noise and share the
// camera's fixed patterns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "camera_test_util.h"

namespace deepsea {
namespace {

using namespace camera_test;

/// Radiance with a dark half (the Poisson path where the read noise is below
/// kGaussianReadNoiseFrom), a bright half and a gradient.
Image scene(int w, int h, double scale) {
    Image img(w, h, 3);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u)
            for (int c = 0; c < 3; ++c)
                img.at(u, v, c) = float(scale * (u < w / 2 ? 0.002 : 1.0) * (1.0 + 0.3 * c) *
                                        (1.0 + std::sin(0.1 * u + 0.07 * v)));
    return img;
}

bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels &&
           std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

void expect_same(const CameraOutput& a, const CameraOutput& b, const std::string& what) {
    EXPECT_TRUE(same_bits(a.image, b.image)) << what;
    EXPECT_TRUE(same_bits(a.raw, b.raw)) << what;
    EXPECT_TRUE(same_bits(a.linear_dn, b.linear_dn)) << what;
    EXPECT_TRUE(same_bits(a.noise_free, b.noise_free)) << what;
}

TEST(CameraNoise, SameBitsInAnyOrderAndAtAnyThreadCount) {
    CameraModel plain;
    CameraModel lens = plain;  // also the lens map and grey world's two passes
    lens.lens.distortion = {-0.12, 0.03, 0.001, -0.002, 0.0};
    lens.processing.white_balance = WhiteBalance::GreyWorld;
    lens.processing.matrix = std::array<double, 9>{1.2, -0.1, -0.1, -0.1, 1.2, -0.1, 0, 0, 1};
    lens.sensor.dark_noise = 1.5;  // the low counts' Poisson path, here and in `mosaic`
    CameraModel mosaic = plain;    // a Bayer mosaic, and one with the lens and grey world
    mosaic.sensor.bayer = BayerPattern::Gbrg;
    mosaic.sensor.dark_noise = 1.5;
    CameraModel lens_mosaic = lens;
    lens_mosaic.sensor.bayer = BayerPattern::Rggb;
    for (const CameraModel& m : {plain, lens, mosaic, lens_mosaic}) {
        const Camera cam = pinhole(203, 61, 150.0);  // a width that leaves vector tails
        const CameraStage stage(m, cam);
        const double full = m.sensor.full_well / stage.electrons_per_radiance(1, 10.0);
        const Image radiance = scene(cam.width, cam.height, 0.4 * full);
        std::vector<CameraOutput> forward(4), backward(4);
        for (int k = 0; k < 4; ++k)
            stage.apply(forward[k], radiance, 100 + k, CameraLayerSet::all(), Parallel(1));
        for (int k : {3, 1, 0, 2})
            stage.apply(backward[k], radiance, 100 + k, CameraLayerSet::all(), Parallel(2, 1));
        for (int k = 0; k < 4; ++k) expect_same(forward[k], backward[k], std::to_string(k));
        CameraOutput alone;  // a frame made on its own, all cores, the default grain
        stage.apply(alone, radiance, 102, CameraLayerSet::all());
        expect_same(forward[2], alone, "alone");
        // Another stage of the same camera: the same frames.
        const CameraStage again(m, cam);
        CameraOutput other;
        again.apply(other, radiance, 101, CameraLayerSet::all(), Parallel(2, 3));
        expect_same(forward[1], other, "another stage");
        // The image as 8-bit codes: the display values quantised as the 8-bit writers do.
        CameraLayerSet codes = CameraLayerSet::all();
        codes.codes8 = true;
        CameraOutput coded;
        stage.apply(coded, radiance, 101, codes, Parallel(2, 3));
        EXPECT_TRUE(coded.image.empty());
        ASSERT_EQ(coded.codes8.size(), forward[1].image.data.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < coded.codes8.size(); ++i) {
            const float x = std::min(std::max(forward[1].image.data[i], 0.0f), 1.0f);
            wrong += coded.codes8[i] != std::uint8_t(x * 255.0f + 0.5f);
        }
        EXPECT_EQ(wrong, 0u);
        EXPECT_TRUE(same_bits(coded.raw, forward[1].raw));
        EXPECT_EQ(coded.width, cam.width);
        EXPECT_EQ(coded.height, cam.height);
    }
}

/// Pearson correlation of two equally sized sequences.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
    double ma = 0, mb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
    ma /= a.size();
    mb /= b.size();
    double sab = 0, saa = 0, sbb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}

TEST(CameraNoise, FramesDifferInTemporalNoiseAndShareTheFixedPattern) {
    CameraModel m = flat_model();
    m.sensor.prnu_percent = 4.0;  // a strong pattern against 1 % shot noise at 10^4 e-
    m.sensor.dsnu = 20.0;
    m.sensor.full_well = 40000.0;
    const Camera cam = pinhole(128, 96, 200.0);
    const CameraStage stage(m, cam);
    Rgb L;
    for (int c = 0; c < 3; ++c) L[c] = 10000.0 / stage.electrons_per_radiance(c, 10.0);
    const Image field = flat(cam.width, cam.height, L);
    const auto frame = [&](const CameraStage& st, std::uint64_t key) {
        CameraOutput out;
        CameraLayerSet set;
        set.linear_dn = true;
        st.apply(out, field, key, set);
        return std::vector<double>(out.linear_dn.data.begin(), out.linear_dn.data.end());
    };
    const std::vector<double> a = frame(stage, 0), b = frame(stage, 1);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
    EXPECT_GT(differ, a.size() * 99 / 100);
    // The fixed pattern is 4 % against 1 % temporal noise: frames of one camera correlate by
    // 16 / 17, another camera's (another seed) not at all.
    EXPECT_NEAR(correlation(a, b), 16.0 / 17.0, 0.01);
    CameraModel other = m;
    other.sensor.seed = 1;
    const std::vector<double> c = frame(CameraStage(other, cam), 0);
    EXPECT_NEAR(correlation(a, c), 0.0, 0.02);
    // The temporal difference carries no pattern: frames 0 - 1 and 2 - 3 are uncorrelated.
    const std::vector<double> d = frame(stage, 2), e = frame(stage, 3);
    std::vector<double> ab(a.size()), de(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) ab[i] = a[i] - b[i], de[i] = d[i] - e[i];
    EXPECT_NEAR(correlation(ab, de), 0.0, 0.02);
    // Neighbouring pixels' temporal noise is uncorrelated too.
    std::vector<double> left(ab.begin(), ab.end() - 3), right(ab.begin() + 3, ab.end());
    EXPECT_NEAR(correlation(left, right), 0.0, 0.02);
}

}  // namespace
}  // namespace deepsea
