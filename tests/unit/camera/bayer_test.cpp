// The Bayer mosaic (docs/bayer.md): each photosite records its pattern's
// channel, the raw and linear layers are mosaics, the bilinear demosaic gives flat fields and
// linear ramps back, and noise_free stays full RGB.
#include "deepsea/camera/bayer.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <string>

#include "camera_test_util.h"
#include "deepsea/camera/sensor.h"
#include "deepsea/optics/schema.h"

namespace deepsea {
namespace {

using namespace camera_test;

constexpr BayerPattern kPatterns[] = {BayerPattern::Rggb, BayerPattern::Bggr, BayerPattern::Grbg,
                                      BayerPattern::Gbrg};

TEST(BayerMosaic, TilesAsNamed) {
    // The 2 x 2 tile read left to right, top to bottom: the letters of the name.
    const char* letters = "RGB";
    for (BayerPattern p : kPatterns) {
        std::string tile;
        for (int v = 0; v < 2; ++v)
            for (int u = 0; u < 2; ++u) tile += letters[bayer_channel(p, u, v)];
        std::string name = bayer_name(p);
        for (char& ch : name) ch = char(std::toupper(ch));
        EXPECT_EQ(tile, name);
        // The tile repeats.
        EXPECT_EQ(bayer_channel(p, 6, 9), bayer_channel(p, 0, 1));
        EXPECT_EQ(bayer_from_name(bayer_name(p)), p);
    }
    EXPECT_FALSE(bayer_from_name("rgbg"));
}

TEST(BayerMosaic, EachPhotositeRecordsItsChannel) {
    // With noise, raw and linear DN: the pattern's channel holds the value, the other two 0.
    // A width that leaves vector tails and a chunk boundary inside a row.
    const Camera cam = pinhole(203, 6, 150.0);
    for (BayerPattern p : kPatterns) {
        CameraModel m = flat_model();
        m.sensor.bayer = p;
        const CameraStage stage(m, cam);
        const double full = m.sensor.full_well / stage.electrons_per_radiance(1, 10.0);
        CameraOutput out;
        stage.apply(out, flat(cam.width, cam.height, Rgb(0.3 * full)), 5, CameraLayerSet::all());
        for (int v = 0; v < cam.height; ++v)
            for (int u = 0; u < cam.width; ++u)
                for (int c = 0; c < 3; ++c) {
                    const bool recorded = bayer_channel(p, u, v) == c;
                    ASSERT_EQ(out.raw.at(u, v, c) > 0.0f, recorded) << u << " " << v << " " << c;
                    ASSERT_EQ(out.linear_dn.at(u, v, c) != 0.0f, recorded);
                }
        // noise_free stays full RGB: every channel.
        EXPECT_GT(mean(out.noise_free, 0), 0.1);
        EXPECT_GT(mean(out.noise_free, 2), 0.1);
    }
}

TEST(BayerMosaic, RecordedValuesAreThoseOfTheFullColourSensor) {
    // A photosite's noise is its channel's in the full-colour sensor (same counter).
    const Camera cam = pinhole(64, 8, 60.0);
    CameraModel rgb = flat_model();
    CameraModel bayer = rgb;
    bayer.sensor.bayer = BayerPattern::Grbg;
    const CameraStage a(rgb, cam), b(bayer, cam);
    const double full = rgb.sensor.full_well / a.electrons_per_radiance(1, 10.0);
    Image radiance = flat(cam.width, cam.height, Rgb(0.2 * full));
    for (int u = 0; u < 20; ++u)  // some values on the exact (Poisson) path
        for (int c = 0; c < 3; ++c) radiance.at(u, 3, c) = float(1e-4 * full);
    CameraOutput x, y;
    CameraLayerSet raw;
    raw.raw = true;
    a.apply(x, radiance, 9, raw);
    b.apply(y, radiance, 9, raw);
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
            const int c = bayer_channel(BayerPattern::Grbg, u, v);
            ASSERT_EQ(x.raw.at(u, v, c), y.raw.at(u, v, c)) << u << " " << v;
        }
}

TEST(BayerMosaic, FlatFieldThroughMosaicAndDemosaic) {
    // Noise off, no falloff: the demosaic of a flat mosaic is the flat field, so the image is
    // the full-colour sensor's, with and without grey world (which counts recorded values only).
    const Camera cam = pinhole(37, 12, 40.0);
    for (WhiteBalance wb : {WhiteBalance::None, WhiteBalance::GreyWorld}) {
        CameraModel rgb = flat_model();
        rgb.sensor.noise = false;
        rgb.processing.white_balance = wb;
        const CameraStage a(rgb, cam);
        const double full = rgb.sensor.full_well / a.electrons_per_radiance(1, 10.0);
        const Image radiance = flat(cam.width, cam.height, Rgb(0.1, 0.4, 0.25) * full);
        CameraOutput want;
        a.apply(want, radiance, 0, CameraLayerSet::all());
        for (BayerPattern p : kPatterns) {
            CameraModel m = rgb;
            m.sensor.bayer = p;
            CameraOutput got;
            CameraStage(m, cam).apply(got, radiance, 0, CameraLayerSet::all());
            for (std::size_t i = 0; i < want.image.data.size(); ++i) {
                ASSERT_NEAR(got.image.data[i], want.image.data[i], 1e-6) << i;
                ASSERT_NEAR(got.noise_free.data[i], want.noise_free.data[i], 1e-6) << i;
            }
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got.white_balance[c], want.white_balance[c], 1e-12);
        }
    }
}

TEST(BayerMosaic, BilinearDemosaicKeepsLinearRampsInside) {
    // Bilinear interpolation is exact for a linear function: away from the border every
    // channel's ramp comes back; at the border it is the mean of the neighbours inside.
    const int w = 12, h = 9;
    const auto ramp = [](int u, int v, int c) { return float(100 + 3 * u + 7 * v + 50 * c); };
    for (BayerPattern p : kPatterns) {
        Image mosaic(w, h, 3);
        for (int v = 0; v < h; ++v)
            for (int u = 0; u < w; ++u) {
                const int c = bayer_channel(p, u, v);
                mosaic.at(u, v, c) = ramp(u, v, c);
            }
        Image rgb;
        demosaic(mosaic, p, rgb);
        for (int v = 1; v < h - 1; ++v)
            for (int u = 1; u < w - 1; ++u)
                for (int c = 0; c < 3; ++c) ASSERT_EQ(rgb.at(u, v, c), ramp(u, v, c));
        // Corner (0, 0): its own channel as recorded.
        const int c00 = bayer_channel(p, 0, 0);
        EXPECT_EQ(rgb.at(0, 0, c00), ramp(0, 0, c00));
    }
}

TEST(BayerMosaic, TooSmallAnImageIsRefusedNamingTheKey) {
    CameraModel m;
    m.sensor.bayer = BayerPattern::Rggb;
    try {
        CameraStage(m, pinhole(1, 8, 10.0));
        FAIL() << "a 1-pixel-wide mosaic was accepted";
    } catch (const SchemaError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("camera.sensor.bayer:", 0), 0u) << e.what();
    }
}

}  // namespace
}  // namespace deepsea
