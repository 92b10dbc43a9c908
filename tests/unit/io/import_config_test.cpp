#include "deepsea/io/import_config.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../message_of.h"
#include "../replaced.h"
#include "../temp_folder.h"
#include "deepsea/camera/camera_stage.h"
#include "deepsea/core/error.h"
#include "deepsea/io/config.h"
#include "deepsea/optics/jerlov.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;
using test::replaced;

// A DeepSeaRenderer config as their test set ships it (keys deepsea ignores included).
const std::string kAuthors =
    "scale_factor: 10.0\n"                                                              // 1
    "image_width_height: [800, 800]\n"                                                  // 2
    "camera_intrinsic_matrix: [600.0, 0.0, 400.0, 0.0, 600.0, 400.0, 0.0, 0.0, 1.0]\n"  // 3
    "water_attenuation_RGB: [0.37, 0.044, 0.035]\n"                                     // 4
    "vsf_type: 1\n"                                                                     // 5
    "light_spectrum_RGB: [0.25, 0.35, 0.4]\n"                                           // 6
    "light_RID_type: 1\n"                                                               // 7
    "num_lights: 2\n"                                                                   // 8
    "light_positions_XYZ: [[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0]]\n"                        // 9
    "light_orientations_RollPitchYaw: [[0.0, 0.536, 0.0], [0.0, -0.536, 0.0]]\n"        // 10
    "refine_depth: false\n";                                                            // 11

class ImportConfig : public test::TempFolderTest {
protected:
    std::string file(const std::string& text) {
        const std::string p = (dir_ / "cfg.yaml").string();
        std::ofstream(p) << text;
        return p;
    }
    /// The ConfigError message for text, or "" if it converts.
    std::string error(const std::string& text) {
        return test::message_of<ConfigError>([&] { import_config(file(text)); });
    }
};

TEST_F(ImportConfig, AuthorsConfigBecomesTheirSetup) {
    const deepsea::Setup s = parse_setup(import_config(file(kAuthors)), "converted.yaml");
    ASSERT_TRUE(s.camera && s.rig && s.water);
    EXPECT_EQ(s.camera->width, 800);
    EXPECT_EQ(s.camera->fx, 600.0);
    EXPECT_EQ(s.camera->cx, 400.0);
    ASSERT_EQ(s.rig->lights.size(), 2u);
    const Light& left = s.rig->lights[0];
    EXPECT_EQ(left.position.x, -0.5);
    // Pitch 0.536 rad about y turns the left lamp toward the optical axis.
    EXPECT_NEAR(left.direction.x, std::sin(0.536), 1e-8);
    EXPECT_NEAR(left.direction.z, std::cos(0.536), 1e-8);
    EXPECT_NEAR(s.rig->lights[1].direction.x, -std::sin(0.536), 1e-8);
    EXPECT_EQ(left.intensity.b, 0.4);
    EXPECT_EQ(left.rid.kind, Rid::Kind::Table);  // light_RID_type 1: TheirLampPatterns
    // Their Kd numbers for Jerlov IB become the measured IB preset, with forward scatter on.
    EXPECT_EQ(s.water->c.r, jerlov_water("IB").c.r);
    EXPECT_EQ(s.water->phase.kind, PhaseKind::PetzoldClear);
    EXPECT_TRUE(s.water->forward.enabled);
}

TEST_F(ImportConfig, TheirLampPatterns) {
    // light_RID_type 1: their lab-measured LED, BXRA_table in DeepSeaRenderer's
    // src/rendering.cpp, interpolated linearly and 0 beyond 90 degrees by their light_RID.
    const std::vector<double> angle{0, 10, 20, 30, 35, 40, 45, 50, 60, 90};
    const std::vector<double> value{1.0, 0.96, 0.87, 0.75, 0.63, 0.5, 0.28, 0.2, 0.12, 0.0};
    const deepsea::Setup s = parse_setup(import_config(file(kAuthors)), "converted.yaml");
    for (const Light& l : s.rig->lights) {
        ASSERT_EQ(l.rid.kind, Rid::Kind::Table) << l.name;
        EXPECT_EQ(l.rid.angle_deg, angle) << l.name;
        EXPECT_EQ(l.rid.value, value) << l.name;
    }
    const Rid& led = s.rig->lights[0].rid;
    const double deg = M_PI / 180.0;
    EXPECT_NEAR(led(0.0), 1.0, 1e-12);
    EXPECT_NEAR(led(42.5 * deg), 0.39, 1e-9);  // halfway between 0.5 and 0.28
    EXPECT_NEAR(led(75.0 * deg), 0.06, 1e-9);
    EXPECT_EQ(led(90.0 * deg), 0.0);
    EXPECT_EQ(led(120.0 * deg), 0.0);

    // light_RID_type 0: their Gaussian, sigma 35 degrees, 0 beyond 90 degrees.
    const deepsea::Setup g = parse_setup(
        import_config(file(replaced(kAuthors, "light_RID_type: 1", "light_RID_type: 0"))),
        "converted.yaml");
    const Rid& gauss = g.rig->lights[1].rid;
    EXPECT_EQ(gauss.kind, Rid::Kind::Gaussian);
    EXPECT_EQ(gauss.sigma_deg, 35.0);
    EXPECT_EQ(gauss.cutoff_deg, 90.0);
    EXPECT_NEAR(gauss(35.0 * deg), std::exp(-0.5), 1e-12);
    EXPECT_EQ(gauss(91.0 * deg), 0.0);
}

TEST_F(ImportConfig, OtherWatersAndPhases) {
    std::string text = replaced(kAuthors, "[0.37, 0.044, 0.035]", "[0.5, 0.2, 0.1]");
    text = replaced(text, "vsf_type: 1", "vsf_type: 4");
    const deepsea::Setup s = parse_setup(import_config(file(text)), "converted.yaml");
    EXPECT_EQ(s.water->c.g, 0.2);
    // Their type 4 evaluates 1 + g^2 + 2 g cos(psi) with g = -0.3: forward-peaked, which is
    // g = +0.3 in the standard convention that deepsea (and Cycles, pbrt) use.
    EXPECT_EQ(s.water->phase.kind, PhaseKind::HenyeyGreenstein);
    EXPECT_EQ(s.water->phase.g, 0.3);
}

TEST_F(ImportConfig, TheirJerlovTypeIIKdBecomesThePreset) {
    // testset_bomb's config names Jerlov II as Kd (0.4, 0.071, 0.06), as IB is (0.37, ...).
    const std::string text = replaced(kAuthors, "[0.37, 0.044, 0.035]", "[0.4, 0.071, 0.06]");
    const std::string yaml = import_config(file(text));
    EXPECT_NE(yaml.find("preset: jerlov:II\n"), std::string::npos) << yaml;
    const deepsea::Setup s = parse_setup(yaml, "converted.yaml");
    EXPECT_EQ(s.water->c.r, jerlov_water("II").c.r);
    EXPECT_EQ(s.water->b.b, jerlov_water("II").b.b);
    EXPECT_EQ(s.water->name, "jerlov-II");
    // Their vsf_type still chooses the phase function.
    EXPECT_EQ(s.water->phase.kind, PhaseKind::PetzoldClear);
}

TEST_F(ImportConfig, FieldOfViewFormOfTheIntrinsics) {
    // One number: their horizontal field of view in radians, f = width / 2 / tan(fov / 2),
    // principal point at (width / 2, height / 2). A one-element list is their form; a bare
    // number means the same.
    const std::string wide = replaced(kAuthors, "[800, 800]", "[640, 480]");
    for (const char* form : {"[1.2]", "1.2"}) {
        const std::string text =
            replaced(wide, "[600.0, 0.0, 400.0, 0.0, 600.0, 400.0, 0.0, 0.0, 1.0]", form);
        const deepsea::Setup s = parse_setup(import_config(file(text)), "converted.yaml");
        const double f = 320.0 / std::tan(0.6);
        EXPECT_NEAR(s.camera->fx, f, 1e-6 * f) << form;
        EXPECT_EQ(s.camera->fy, s.camera->fx) << form;
        EXPECT_EQ(s.camera->cx, 320.0) << form;
        EXPECT_EQ(s.camera->cy, 240.0) << form;
        EXPECT_EQ(s.camera->width, 640) << form;
        EXPECT_EQ(s.camera->height, 480) << form;
    }
}

/// The display value the converted camera gives a flat field of radiance L (noise is off).
Rgb displayed(const deepsea::Setup& s, Rgb L) {
    const Camera cam{16, 8, 20.0, 20.0, 7.5, 3.5};
    CameraStage stage(*s.camera_model, cam);
    CameraOutput out;
    Image radiance(cam.width, cam.height, 3);
    for (std::size_t i = 0; i < radiance.data.size(); ++i) radiance.data[i] = float(L[int(i % 3)]);
    stage.apply(out, radiance, 0);
    const std::size_t corner = 3 * std::size_t(cam.width * cam.height - 1);  // falloff is off
    return {out.image.data[corner], out.image.data[corner + 1], out.image.data[corner + 2]};
}

TEST_F(ImportConfig, TheirCameraBecomesTheCameraStage) {
    // Their writer: 255 * scale_factor * pi * L (their albedo is the 8-bit value, their direct
    // term has no 1/pi), times white_balance, clipped at 255, no curve.
    const std::string text =
        kAuthors + "white_balance: [2.28613, 1.0, 1.361328]\nauto_iso: false\n";
    const deepsea::Setup s = parse_setup(import_config(file(text)), "converted.yaml");
    ASSERT_TRUE(s.camera_model);
    const CameraModel& m = *s.camera_model;
    EXPECT_FALSE(m.sensor.noise);
    EXPECT_FALSE(m.lens.vignetting.natural);
    EXPECT_EQ(m.processing.curve, OutputCurve::Linear);
    EXPECT_EQ(m.processing.white_balance, WhiteBalance::Gains);
    EXPECT_EQ(m.processing.gains.r, 2.28613);
    const double wb[3] = {2.28613, 1.0, 1.361328}, s10 = 10.0 * M_PI;
    const Rgb L{0.2 / s10, 0.5 / s10, 0.6 / s10};  // their 0.2 * 2.29, 0.5, 0.6 * 1.36 of 255
    const Rgb got = displayed(s, L);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], wb[c] * s10 * L[c], 1e-4) << c;
    // Clipped at 1 where theirs clips at 255.
    EXPECT_EQ(displayed(s, Rgb(2.0 / s10)).g, 1.0f);
    // A gain below 1: the raw signal keeps the headroom their clip after the gain has.
    const deepsea::Setup low = parse_setup(
        import_config(file(kAuthors + "white_balance: [0.5, 1.0, 2.0]\n")), "converted.yaml");
    const Rgb bright = displayed(low, Rgb(1.5 / s10));
    EXPECT_NEAR(bright.r, 0.75, 1e-4);
    EXPECT_EQ(bright.g, 1.0f);
    EXPECT_EQ(bright.b, 1.0f);
}

TEST_F(ImportConfig, TheirAutoIsoAndAConfigWithoutScaleFactor) {
    // auto_iso: their writer stretches [min, max] and skips white_balance: no gains here.
    const deepsea::Setup a = parse_setup(
        import_config(file(kAuthors + "white_balance: [2.0, 1.0, 1.5]\nauto_iso: true\n")),
        "converted.yaml");
    ASSERT_TRUE(a.camera_model);
    EXPECT_EQ(a.camera_model->processing.white_balance, WhiteBalance::None);
    EXPECT_NEAR(displayed(a, Rgb(0.5 / (10.0 * M_PI))).g, 0.5, 1e-4);
    // No scale_factor: no camera stage (radiance out, as before).
    const deepsea::Setup none = parse_setup(
        import_config(file(replaced(kAuthors, "scale_factor: 10.0\n", ""))), "converted.yaml");
    EXPECT_FALSE(none.camera_model);
}

TEST_F(ImportConfig, BadInputNamesFileLineAndKey) {
    const std::string f = (dir_ / "cfg.yaml").string();
    auto starts = [&](const std::string& text, const std::string& want) {
        const std::string got = error(text);
        EXPECT_EQ(got.rfind(f + want, 0), 0u) << "got: " << got << "\nwant: " << f + want;
    };
    starts("camera: {width: 3}\n", ":1: (top level): not a DeepSeaRenderer config");
    starts(replaced(kAuthors, "600.0, 400.0, 0.0, 0.0, 1.0]", "600.0]"),
           ":3: camera_intrinsic_matrix: expected a list of 9 numbers (K row by row) or 1 (the "
           "horizontal field of view in radians), got 5");
    // A field of view is in radians, less than pi: 80 is degrees.
    starts(replaced(kAuthors, "[600.0, 0.0, 400.0, 0.0, 600.0, 400.0, 0.0, 0.0, 1.0]", "[80]"),
           ":3: camera_intrinsic_matrix: field of view must be in (0, pi) radians, got 80");
    starts(replaced(kAuthors, "[600.0, 0.0, 400.0, 0.0, 600.0, 400.0, 0.0, 0.0, 1.0]", "0"),
           ":3: camera_intrinsic_matrix: field of view must be in (0, pi) radians, got 0");
    starts(replaced(kAuthors, "num_lights: 2", "num_lights: 3"),
           ":9: light_positions_XYZ: expected 3 entries");
    starts(replaced(kAuthors, "num_lights: 2", "num_lights: 0"), ":8: num_lights: must be >= 1");
    starts(replaced(kAuthors, "vsf_type: 1", "vsf_type: 7"), ":5: vsf_type: expected 1, 2, 3 or 4");
    starts(replaced(kAuthors, "vsf_type: 1\n", ""), ":1: vsf_type: missing required key");
    starts(replaced(kAuthors, "light_RID_type: 1", "light_RID_type: 2"),
           ":7: light_RID_type: expected 0 (their Gaussian) or 1 (their lab-measured LED)");
    starts(replaced(kAuthors, "[0.25, 0.35, 0.4]", "[0.25, x, 0.4]"),
           ":6: light_spectrum_RGB[1]: expected a number");
    starts(replaced(kAuthors, "scale_factor: 10.0", "scale_factor: 0"),
           ":1: scale_factor: must be > 0, got 0");
    starts(kAuthors + "white_balance: [1.0, 0, 1.0]\n",
           ":12: white_balance: each gain must be > 0, got 0");
    // Values their format allows but deepsea's schema does not: named in the converted text.
    const std::string zero_fx = error(replaced(kAuthors, "[600.0, 0.0, 400.0", "[0.0, 0.0, 400.0"));
    EXPECT_NE(zero_fx.find("(converted)"), std::string::npos) << zero_fx;
    EXPECT_NE(zero_fx.find("camera.fx: must be > 0"), std::string::npos) << zero_fx;
    EXPECT_THROW(import_config((dir_ / "none.yaml").string()), IoError);
}

TEST_F(ImportConfig, WritesAtomically) {
    const std::string in = file(kAuthors);
    const std::string out = (dir_ / "out.yaml").string();
    import_config(in, out);
    std::ifstream is(out);
    const std::string written((std::istreambuf_iterator<char>(is)), {});
    EXPECT_EQ(written, import_config(in));
    // A failed conversion leaves nothing behind, not even a temporary.
    const std::string bad_out = (dir_ / "bad.yaml").string();
    std::ofstream(in) << "camera: {width: 3}\n";
    EXPECT_THROW(import_config(in, bad_out), ConfigError);
    EXPECT_FALSE(fs::exists(bad_out));
    int files = 0;
    for (const auto& e : fs::directory_iterator(dir_)) files += e.is_regular_file();
    EXPECT_EQ(files, 2);  // cfg.yaml, out.yaml
    std::ofstream(in) << kAuthors;
    EXPECT_THROW(import_config(in, (dir_ / "no/such/dir/x.yaml").string()), IoError);
}

}  // namespace
}  // namespace deepsea
