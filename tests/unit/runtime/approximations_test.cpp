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
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "deepsea/asset/asset_file.h"
#include "deepsea/bake/bake.h"
#include "deepsea/colour/srgb.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/water_presets.h"
#include "deepsea/runtime/asset_backscatter.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/forward_psf_blur.h"
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

/// No lamp light on surfaces: the image is B alone, so that its error per pixel is the
/// backscatter rows' own.
class NoLamps : public IrradianceSource {
public:
    void irradiance_row(const RowGeometry& g, float* out) const override {
        std::fill(out, out + 3 * std::size_t(g.n), 0.0f);
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

Worst compare(const Camera& cam, const Water& water, const Frame& frame,
              const BackscatterSource* backscatter = nullptr,
              const Rig& rig = testing::two_lamps()) {
    const AnalyticLamps lamps(rig, water);
    const NoBackscatter none;
    const BackscatterSource& bs = backscatter ? *backscatter : none;
    Compositor exact(cam, water, lamps, bs), approx(cam, water, lamps, bs);
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

TEST(Approximations, TheOnePixelScaleIsAddedUnblurred) {
    // ForwardPsfBlur::set_identity_blurs alone (block distances off in both): the 1 px scale's
    // Gaussian of 0.15 cells left out moves F by 1e-9 of its maximum (its taps beside the
    // centre) plus float rounding; on the seafloor, a plane with a depth step 0.3 m away and
    // stripes of open water, in clear and turbid water, at 400 px and on a 64x48 camera, and
    // the authors' frames 1 and 5
    FlightParams fp;
    fp.camera = Camera{400, 400, 300.0, 300.0, 200.0, 200.0};
    std::vector<std::pair<Camera, Frame>> frames{{fp.camera, render_flight_frame(fp, 1)}};
    for (const Camera& cam : {fp.camera, Camera{64, 48, 48.0, 48.0, 31.5, 23.5}}) {
        const testing::PlaneScene p = testing::plane_scene(cam, 0.3);
        Frame f;
        f.rgb = p.rgb;
        f.depth = p.depth;
        for (int v = 0; v < cam.height; v += 7)  // rows of open water
            for (int u = 0; u < cam.width; ++u) f.depth.at(u, v) = 0.0f;
        frames.emplace_back(cam, f);
    }
    const std::filesystem::path dir =
        std::filesystem::path(DEEPSEA_SHARED_DATA) / "rgbd" / "seafloor-descent";
    for (const char* name : {"frame_0001", "frame_0005"}) {  // the authors' frames, where present
        if (!std::filesystem::exists(dir / (std::string(name) + ".png"))) continue;
        Frame f;
        f.rgb = read_color((dir / (std::string(name) + ".png")).string());
        f.depth = read_depth((dir / (std::string(name) + "_depth.exr")).string());
        frames.emplace_back(demo_camera(), f);
    }
    for (auto& [cam, frame] : frames) {
        // distances as the compositor hands them over: open water (NaN, inf, <= 0) as 0
        for (float& z : frame.depth.data) z = z > 0.0f && z < 1e30f ? z : 0.0f;
        for (const char* water : {"deep:clear", "jerlov:5C"}) {
            const ForwardPsf psf(with_forward(water), cam.fx, cam.width, cam.height);
            ForwardPsfBlur fast(psf), exact(psf);
            fast.set_block_distances(false);
            exact.set_block_distances(false);
            exact.set_identity_blurs(false);
            fast.prepare(frame.rgb, frame.depth);
            exact.prepare(frame.rgb, frame.depth);
            EXPECT_EQ(fast.unblurred_scales(), 1) << water;  // the shortcut was taken
            EXPECT_EQ(exact.unblurred_scales(), 0) << water;
            std::vector<float> a(3 * std::size_t(cam.width)), b(a.size());
            double peak = 0.0, diff = 0.0;
            for (int v = 0; v < cam.height; ++v) {
                exact.row(v, a.data());
                fast.row(v, b.data());
                for (std::size_t i = 0; i < a.size(); ++i) {
                    peak = std::max(peak, double(std::fabs(a[i])));
                    diff = std::max(diff, double(std::fabs(a[i] - b[i])));
                }
            }
            std::printf("%dx%d, %s: unblurred 1 px scale %.2e of F's max\n", cam.width, cam.height,
                        water, diff / peak);
            EXPECT_LE(diff, 1e-7 * peak) << water;
        }
    }
}

namespace {

/// The backscatter rows' worst error relative to each pixel's own B (the bound in
/// backscatter_rows.h is 5e-4), and the fraction of values they changed (so that a test knows
/// the rows were interpolated at all).
struct RowsWorst {
    double relative = 0.0;
    double changed = 0.0;
};

RowsWorst compare_rows(const Camera& cam, const Water& water, const Frame& frame,
                       const BackscatterSource& bs) {
    const NoLamps dark;
    Compositor exact(cam, water, dark, bs), approx(cam, water, dark, bs);
    exact.set_exact(true);
    Layers a, b;
    exact.composite(a, frame, LayerSet::Final);
    approx.composite(b, frame, LayerSet::Final);
    RowsWorst w;
    std::size_t changed = 0;
    for (std::size_t i = 0; i < a.final.data.size(); ++i) {
        const double e = a.final.data[i], d = std::fabs(e - double(b.final.data[i]));
        changed += d > 0.0;
        if (d > 0.0) w.relative = std::max(w.relative, e > 0.0 ? d / e : 1.0);
    }
    w.changed = double(changed) / double(a.final.data.size());
    return w;
}

/// Both comparisons: B alone against its bound (plus float rounding), and the image with the
/// lamps against issue 23's (one code, 0.1 % of the layers' maxima).
void expect_rows_within_bounds(const Camera& cam, const Rig& rig, const Water& water,
                               const Asset& asset, const Frame& frame, const std::string& what,
                               double min_changed = 0.0) {
    const AssetBackscatter bs(asset, cam);
    const RowsWorst r = compare_rows(cam, water, frame, bs);
    std::printf("%s: backscatter rows %.2e of B (%.1f %% of values changed)\n", what.c_str(),
                r.relative, 100.0 * r.changed);
    EXPECT_LE(r.relative, 5e-4 + 1e-6) << what;
    EXPECT_GE(r.changed, min_changed) << what;
    expect_within_bounds(compare(cam, water, frame, &bs, rig), what + ", lamps");
}

Asset bake_for(const Camera& cam, const Rig& rig, const Water& water) {
    BakeSettings s;
    s.step = std::max(2, cam.width / 50);  // the demo's 16 px at 800 px, scaled
    s.check = false;
    return bake(cam, rig, water, s);
}

}  // namespace

TEST(Approximations, BackscatterRowsStayWithinTheirBoundOnSeafloorFrames) {
    // the demo's view at 200 px (rows interpolated two apart), looking down in clear water and
    // ahead over a rougher floor in coastal water
    struct View {
        double pitch, altitude, relief;
        const char* water;
    };
    FlightParams fp;
    fp.camera = Camera{200, 200, 150.0, 150.0, 100.0, 100.0};
    const Rig rig = testing::two_lamps();
    for (const View view : {View{0.0, 3.0, 1.0, "deep:clear"}, View{50.0, 1.5, 2.5, "jerlov:3C"}}) {
        const Water w = with_forward(view.water);
        fp.pitch_deg = view.pitch;
        fp.altitude = view.altitude;
        fp.relief = view.relief;
        // (at least a tenth of the values interpolated: 19-49 % in these views and waters)
        expect_rows_within_bounds(
            fp.camera, rig, w, bake_for(fp.camera, rig, w), render_flight_frame(fp, 1),
            "seafloor pitch " + std::to_string(int(view.pitch)) + ", " + view.water, 0.1);
    }
}

TEST(Approximations, BackscatterRowsStayWithinTheirBoundOnHostileFrames) {
    const Water w = with_forward("deep:clear");
    const Camera cam = testing::small_camera();
    const Rig rig = testing::two_lamps();
    const Asset asset = bake_for(cam, rig, w);
    // a tilted plane with a depth step and every kind of open water; the same 0.3 m away
    for (const double z0 : {3.0, 0.3}) {
        const testing::PlaneScene s = testing::plane_scene(cam, z0);
        Frame frame;
        frame.rgb = s.rgb;
        frame.depth = s.depth;
        expect_rows_within_bounds(cam, rig, w, asset, frame,
                                  "plane with a step at " + std::to_string(z0) + " m");
    }
    // horizontal stripes of surface and open water four rows apart (every looked-up row meets
    // the other kind), and a frame of open water alone
    Frame stripes;
    stripes.rgb = Image(cam.width, cam.height, 3, 0.4f);
    stripes.depth = Image(cam.width, cam.height, 1);
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) stripes.depth.at(u, v) = (v / 2) % 2 ? 2.0f : 0.0f;
    expect_rows_within_bounds(cam, rig, w, asset, stripes, "stripes of open water");
    Frame open = stripes;
    std::fill(open.depth.data.begin(), open.depth.data.end(), 0.0f);
    expect_rows_within_bounds(cam, rig, w, asset, open, "open water", 0.0);
    // a 64x48 camera (the last rows fewer apart), with the demo's lamps and with pencil beams
    // (3 degree lamps), whose backscatter changes fast across the frame
    const Camera tiny{64, 48, 48.0, 48.0, 31.5, 23.5};
    Rig pencil = rig;
    for (Light& l : pencil.lights) l.rid.sigma_deg = 3.0;
    for (const Rig* r : {&rig, static_cast<const Rig*>(&pencil)}) {
        const testing::PlaneScene t = testing::plane_scene(tiny, 2.0, 0.6);
        Frame f;
        f.rgb = t.rgb;
        f.depth = t.depth;
        expect_rows_within_bounds(tiny, *r, w, bake_for(tiny, *r, w), f,
                                  r == &rig ? "64x48 camera" : "64x48 camera, pencil beams");
    }
}

TEST(Approximations, BackscatterRowsOnAGivenAssetAndFrames) {
    // Measures the bound on large frames (docs/runtime.md, "Bounded approximations"): an
    // asset and a folder of its camera's frames (name.png beside name_depth.exr).
    const char* path = std::getenv("DEEPSEA_APPROX_ASSET");
    const char* dir = std::getenv("DEEPSEA_APPROX_FRAMES");
    if (!path || !dir) GTEST_SKIP() << "set DEEPSEA_APPROX_ASSET and DEEPSEA_APPROX_FRAMES";
    const Asset asset = load_asset(path);
    std::vector<std::filesystem::path> colour;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (e.path().extension() == ".png" && name.find("_depth") == std::string::npos)
            colour.push_back(e.path());
    }
    std::sort(colour.begin(), colour.end());
    ASSERT_FALSE(colour.empty()) << dir;
    for (const auto& png : colour) {
        Frame frame;
        frame.rgb = read_color(png.string());
        frame.depth =
            read_depth((png.parent_path() / (png.stem().string() + "_depth.exr")).string());
        expect_rows_within_bounds(asset.info.camera, asset.info.rig, asset.info.water, asset, frame,
                                  png.filename().string());
    }
}

}  // namespace deepsea
