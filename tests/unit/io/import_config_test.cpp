#include "deepsea/io/import_config.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "../message_of.h"
#include "../temp_folder.h"
#include "deepsea/core/error.h"
#include "deepsea/io/config.h"
#include "deepsea/optics/jerlov.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

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
    static std::string replaced(std::string text, const std::string& from, const std::string& to) {
        const auto p = text.find(from);
        EXPECT_NE(p, std::string::npos) << from;
        return p == std::string::npos ? text : text.replace(p, from.size(), to);
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
    EXPECT_EQ(left.rid.kind, Rid::Kind::Gaussian);
    EXPECT_EQ(left.rid.sigma_deg, 35.0);
    // Their Kd numbers for Jerlov IB become the measured IB preset, with forward scatter on.
    EXPECT_EQ(s.water->c.r, jerlov_water("IB").c.r);
    EXPECT_EQ(s.water->phase.kind, PhaseKind::PetzoldClear);
    EXPECT_TRUE(s.water->forward.enabled);
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
    starts(replaced(kAuthors, "[0.25, 0.35, 0.4]", "[0.25, x, 0.4]"),
           ":6: light_spectrum_RGB[1]: expected a number");
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
