// The compositor's bounded approximations (Compositor::set_exact; docs/runtime.md, "Bounded
// approximations") against its exact path on realistic frames: the procedural seafloor as
// `deepsea scene` renders it (the demo's camera, looking down and ahead) and the authors' real
// frames from ../shared (skipped where absent). Each layer an approximation touches stays
// within 0.1 % of that layer's maximum, and the final image within one 8-bit code of the exact
// one at the exact image's automatic exposure.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "deepsea/colour/srgb.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/water_presets.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/lamps.h"
#include "deepsea/scene/flight.h"
#include "runtime_fixtures.h"

namespace deepsea {

namespace {

/// No water light: the final image is D + F alone, so that the forward layer's share of it
/// (what the approximations touch) is as large as it can be.
class NoBackscatter : public BackscatterSource {
public:
    void backscatter_row(int, int n, const float*, float* out) const override {
        std::fill(out, out + 3 * n, 0.0f);
    }
};

Camera demo_camera() { return Camera{800, 800, 600.0, 600.0, 400.0, 400.0}; }

/// The demo's water with forward scatter from the phase function.
Water with_forward(const std::string& preset) {
    Water w = water_preset(preset);
    w.forward = phase_function_forward_scatter();
    return w;
}

/// Worst differences of the approximate path from the exact one.
struct Worst {
    double forward = 0.0;  ///< max |diff| / the exact forward layer's max (every layer)
    double direct = 0.0;   ///< the same for the direct layer
    double final = 0.0;    ///< the same for the image alone (LayerSet::Final)
    int codes = 0;         ///< max |diff| of the final image's 8-bit codes, either layer set
    double changed = 0.0;  ///< the fraction of the image's codes that differ
};

double relative(const Image& exact, const Image& approx) {
    double peak = 0.0, diff = 0.0;
    for (std::size_t i = 0; i < exact.data.size(); ++i) {
        peak = std::max(peak, double(std::fabs(exact.data[i])));
        diff = std::max(diff, double(std::fabs(exact.data[i] - approx.data[i])));
    }
    return peak > 0.0 ? diff / peak : diff;
}

Worst compare(const Camera& cam, const Water& water, const Frame& frame) {
    const Rig rig = testing::two_lamps();
    const AnalyticLamps lamps(rig, water);
    const NoBackscatter none;
    Compositor exact(cam, water, lamps, none), approx(cam, water, lamps, none);
    exact.set_exact(true);
    Layers a, b, only;
    exact.composite(a, frame);
    approx.composite(b, frame);
    approx.composite(only, frame, LayerSet::Final);
    Worst w;
    w.forward = relative(a.forward, b.forward);
    w.direct = relative(a.direct, b.direct);
    w.final = std::max(relative(a.final, b.final), relative(a.final, only.final));
    const double k = exposure_factor(Exposure{}, a.final);
    const std::size_t n = a.final.data.size();
    std::vector<std::uint8_t> ca(n), cb(n);
    srgb_encode(a.final.data.data(), n, k, ca.data());
    std::size_t changed = 0;
    for (const Image* im : {&b.final, &only.final}) {
        srgb_encode(im->data.data(), n, k, cb.data());
        for (std::size_t i = 0; i < n; ++i) {
            w.codes = std::max(w.codes, std::abs(ca[i] - cb[i]));
            changed += ca[i] != cb[i];
        }
    }
    w.changed = double(changed) / double(2 * n);
    return w;
}

void expect_within_bounds(const Worst& w, const std::string& what) {
    std::printf(
        "%s: of the layer's max forward %.2e, direct %.2e, final %.2e; final codes %d (%.4f %% "
        "changed)\n",
        what.c_str(), w.forward, w.direct, w.final, w.codes, 100.0 * w.changed);
    EXPECT_LE(w.forward, 1e-3) << what;
    EXPECT_LE(w.direct, 1e-3) << what;
    EXPECT_LE(w.final, 1e-3) << what;
    EXPECT_LE(w.codes, 1) << what;
}

}  // namespace

TEST(Approximations, SeafloorFramesStayWithinTheirBounds) {
    // the demo flight (looking down from 3 m) and a survey looking ahead over a rougher floor,
    // in the demo's clear water and in a coastal one (more scattering orders, more basis
    // functions)
    struct View {
        double pitch, altitude, relief;
    };
    for (const View view : {View{0.0, 3.0, 1.0}, View{50.0, 1.5, 2.5}}) {
        FlightParams fp;
        // the demo camera's field of view at 400 px (a 800 px seafloor frame takes 10 s)
        fp.camera = Camera{400, 400, 300.0, 300.0, 200.0, 200.0};
        fp.pitch_deg = view.pitch;
        fp.altitude = view.altitude;
        fp.relief = view.relief;
        const Frame frame = render_flight_frame(fp, 1);
        for (const char* water : {"deep:clear", "jerlov:3C"}) {
            expect_within_bounds(
                compare(fp.camera, with_forward(water), frame),
                "seafloor pitch " + std::to_string(int(view.pitch)) + ", " + water);
        }
    }
}

TEST(Approximations, RealFramesStayWithinTheirBounds) {
    const std::filesystem::path dir =
        std::filesystem::path(DEEPSEA_SHARED_DATA) / "rgbd" / "seafloor-descent";
    if (!std::filesystem::exists(dir / "frame_0001.png"))
        GTEST_SKIP() << "no ../shared/data (the authors' frames): " << dir;
    for (const char* name : {"frame_0001", "frame_0005"}) {
        Frame frame;
        frame.rgb = read_color((dir / (std::string(name) + ".png")).string());
        frame.depth = read_depth((dir / (std::string(name) + "_depth.exr")).string());
        expect_within_bounds(compare(demo_camera(), with_forward("deep:clear"), frame),
                             std::string("real ") + name + ", deep:clear");
    }
}

}  // namespace deepsea
