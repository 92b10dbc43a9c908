// The camera / rig / water schema on the strict reader (src/io/config.cpp): what each section
// accepts, its defaults and presets, and where each error is reported. The reader on its own
// is yaml_reader_test.cpp; the ranges on their own tests/unit/optics/schema_test.cpp.
#include "deepsea/io/config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../replaced.h"
#include "../temp_folder.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/deep_ocean.h"
#include "deepsea/optics/jerlov.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

// Line numbers matter: the error tests below refer to them.
const std::string kValid =
    "camera:\n"                                                           // 1
    "  width: 800\n"                                                      // 2
    "  height: 600\n"                                                     // 3
    "  fx: 600.0\n"                                                       // 4
    "  fy: 600.0\n"                                                       // 5
    "  cx: 399.5\n"                                                       // 6
    "  cy: 299.5\n"                                                       // 7
    "rig:\n"                                                              // 8
    "  name: two-lamps\n"                                                 // 9
    "  lights:\n"                                                         // 10
    "    - name: left\n"                                                  // 11
    "      position: [-0.5, 0.0, 0.0]\n"                                  // 12
    "      direction: [0.51, 0.0, 0.86]\n"                                // 13
    "      intensity: [1.0, 1.0, 1.0]\n"                                  // 14
    "      rid: {gaussian: {sigma_deg: 35}}\n"                            // 15
    "      cutoff_deg: 90\n"                                              // 16
    "    - position: [0.5, 0, 0]\n"                                       // 17
    "      direction: [0, 0, 2]\n"                                        // 18
    "      intensity: [2, 2, 2]\n"                                        // 19
    "      rid: {table: {angle_deg: [0, 30, 60], value: [1, 0.5, 0]}}\n"  // 20
    "water:\n"                                                            // 21
    "  name: mine\n"                                                      // 22
    "  attenuation: [0.40, 0.20, 0.18]\n"                                 // 23
    "  scattering: [0.12, 0.12, 0.13]\n"                                  // 24
    "  phase: {henyey_greenstein: {g: 0.9}}\n"                            // 25
    "  forward_scatter: {G: [0.3, 0.1, 0.1], k: 0.05}\n";                 // 26

using test::replaced;

TEST(Config, FullValidConfigParses) {
    const deepsea::Setup s = parse_setup(kValid, "cfg.yaml");
    ASSERT_TRUE(s.camera && s.rig && s.water);
    EXPECT_EQ(s.camera->width, 800);
    EXPECT_EQ(s.camera->height, 600);
    EXPECT_EQ(s.camera->fx, 600.0);
    EXPECT_EQ(s.camera->cy, 299.5);

    EXPECT_EQ(s.rig->name, "two-lamps");
    ASSERT_EQ(s.rig->lights.size(), 2u);
    const Light& l = s.rig->lights[0];
    EXPECT_EQ(l.name, "left");
    EXPECT_EQ(l.position.x, -0.5);
    EXPECT_NEAR(length(l.direction), 1.0, 1e-15);
    EXPECT_NEAR(l.direction.x / l.direction.z, 0.51 / 0.86, 1e-12);
    EXPECT_EQ(l.rid.kind, Rid::Kind::Gaussian);
    EXPECT_EQ(l.rid.sigma_deg, 35.0);
    EXPECT_EQ(l.rid.cutoff_deg, 90.0);
    const Light& r = s.rig->lights[1];
    EXPECT_EQ(r.name, "light2");
    EXPECT_EQ(r.direction.z, 1.0);
    EXPECT_EQ(r.intensity.g, 2.0);
    EXPECT_EQ(r.rid.kind, Rid::Kind::Table);
    EXPECT_EQ(r.rid.angle_deg, (std::vector<double>{0, 30, 60}));
    EXPECT_EQ(r.rid.value, (std::vector<double>{1, 0.5, 0}));
    EXPECT_EQ(r.rid.cutoff_deg, 180.0);

    const Water& w = *s.water;
    EXPECT_EQ(w.name, "mine");
    EXPECT_EQ(w.c.r, 0.40);
    EXPECT_EQ(w.b.b, 0.13);
    EXPECT_EQ(w.phase.kind, PhaseKind::HenyeyGreenstein);
    EXPECT_EQ(w.phase.g, 0.9);
    EXPECT_TRUE(w.forward.enabled);
    EXPECT_EQ(w.forward.G.r, 0.3);
    EXPECT_EQ(w.forward.k, 0.05);
}

struct BadCase {
    std::string from, to;
    int line;
    std::string key;
};

TEST(Config, EachBadInputNamesFileLineAndKey) {
    const std::vector<BadCase> cases = {
        {"  fx: 600.0", "  fx: \"600\"", 4, "camera.fx"},
        {"  fx: 600.0", "  fx: abc", 4, "camera.fx"},
        {"  fx: 600.0", "  fx: -1", 4, "camera.fx"},
        {"  fx: 600.0", "  fx: [600]", 4, "camera.fx"},
        {"  width: 800", "  width: 800.5", 2, "camera.width"},
        {"  width: 800", "  width: 0", 2, "camera.width"},
        {"  width: 800", "  widht: 800", 2, "camera.widht"},
        {"  cy: 299.5\n", "", 1, "camera.cy"},
        {"  height: 600", "  height: 600\n  height: 600", 4, "camera.height"},
        {"      position: [-0.5, 0.0, 0.0]", "      position: [-0.5, 0.0]", 12,
         "rig.lights[0].position"},
        {"      position: [-0.5, 0.0, 0.0]", "      position: [-0.5, x, 0.0]", 12,
         "rig.lights[0].position[1]"},
        {"      direction: [0.51, 0.0, 0.86]", "      direction: [0, 0, 0]", 13,
         "rig.lights[0].direction"},
        {"      position: [-0.5, 0.0, 0.0]", "      position: [0, 0, 0]", 12,
         "rig.lights[0].position"},
        {"    - position: [0.5, 0, 0]", "    - position: [0.005, 0, 0.01]", 17,
         "rig.lights[1].position"},
        {"      intensity: [1.0, 1.0, 1.0]", "      intensity: [1.0, -1.0, 1.0]", 14,
         "rig.lights[0].intensity"},
        {"      intensity: [1.0, 1.0, 1.0]\n", "", 11, "rig.lights[0].intensity"},
        {"sigma_deg: 35", "sigma_deg: 0", 15, "rig.lights[0].rid.gaussian.sigma_deg"},
        {"{gaussian: {sigma_deg: 35}}", "{gauss: {sigma_deg: 35}}", 15, "rig.lights[0].rid.gauss"},
        {"      cutoff_deg: 90", "      cutoff_deg: 181", 16, "rig.lights[0].cutoff_deg"},
        {"      cutoff_deg: 90", "      cutoff: 90", 16, "rig.lights[0].cutoff"},
        {"angle_deg: [0, 30, 60]", "angle_deg: [0, 60, 30]", 20,
         "rig.lights[1].rid.table.angle_deg[2]"},
        {"angle_deg: [0, 30, 60]", "angle_deg: [0, 30, 200]", 20,
         "rig.lights[1].rid.table.angle_deg[2]"},
        {"value: [1, 0.5, 0]", "value: [1, 0.5]", 20, "rig.lights[1].rid.table.value"},
        {"value: [1, 0.5, 0]", "value: [1, -0.5, 0]", 20, "rig.lights[1].rid.table.value[1]"},
        {"    - position: [0.5, 0, 0]", "    - name: left\n      position: [0.5, 0, 0]", 17,
         "rig.lights[1]"},
        {"  scattering: [0.12, 0.12, 0.13]", "  scattering: [0.5, 0.12, 0.13]", 24,
         "water.scattering"},
        {"  attenuation: [0.40, 0.20, 0.18]\n", "", 21, "water.attenuation"},
        {"g: 0.9", "g: 1.0", 25, "water.phase.henyey_greenstein.g"},
        {"  phase: {henyey_greenstein: {g: 0.9}}", "  phase: {petzold: murky}", 25,
         "water.phase.petzold"},
        {"  phase: {henyey_greenstein: {g: 0.9}}", "  phase: rayleigh", 25, "water.phase"},
        {"k: 0.05", "k: -1", 26, "water.forward_scatter.k"},
        {"G: [0.3, 0.1, 0.1]", "G: [0.5, 0.1, 0.1]", 26, "water.forward_scatter.G"},
        {"{G: [0.3, 0.1, 0.1], k: 0.05}", "maybe", 26, "water.forward_scatter"},
        {"{G: [0.3, 0.1, 0.1], k: 0.05}", "{G: [0.3, 0.1, 0.1]}", 26, "water.forward_scatter.k"},
        {"  name: mine", "  name: mine\n  preset: jerlov:XX", 23, "water.preset"},
        {"  name: mine", "  name: mine\n  preset: deep:murky", 23, "water.preset"},
        {"  name: mine", "  name: mine\n  preset: petzold", 23, "water.preset"},
        {"  name: mine", "  name: mine\n  colour: blue", 23, "water.colour"},
        {"water:", "weather:", 21, "weather"},
    };
    for (const auto& c : cases) {
        const std::string text = replaced(kValid, c.from, c.to);
        try {
            parse_setup(text, "cfg.yaml");
            ADD_FAILURE() << "no error for " << c.to;
        } catch (const ConfigError& e) {
            const std::string want = "cfg.yaml:" + std::to_string(c.line) + ": " + c.key + ": ";
            EXPECT_EQ(std::string(e.what()).rfind(want, 0), 0u)
                << "got: " << e.what() << "\nwant prefix: " << want;
        }
    }
}

TEST(Config, EmptyLightListAndEmptyTextAreErrors) {
    const std::string text =
        "rig:\n"
        "  lights: []\n";
    EXPECT_THROW(parse_setup(text, "r.yaml"), ConfigError);
    try {
        parse_setup(text, "r.yaml");
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("r.yaml:2: rig.lights: ", 0), 0u) << e.what();
    }
    EXPECT_THROW(parse_setup("", "e.yaml"), ConfigError);
    EXPECT_THROW(parse_setup("camera:\n", "e.yaml"), ConfigError);
    // A map without sections (found by fuzz_config: it parsed, printed as "", and the printed
    // text was refused).
    for (const char* text : {"{}", "{}\n", "--- {}\n"}) {
        try {
            parse_setup(text, "m.yaml");
            ADD_FAILURE() << "accepted: " << text;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("m.yaml:1: (top level): empty configuration"),
                      std::string::npos)
                << e.what();
        }
    }
}

TEST(Config, YamlSyntaxErrorNamesFileAndLine) {
    try {
        parse_setup("camera:\n  width: 1\n  fx: [600\n", "syn.yaml");
        FAIL();
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("syn.yaml:", 0), 0u) << msg;
        EXPECT_NE(msg.find("syntax"), std::string::npos) << msg;
    }
}

TEST(Config, PresetAndOverrides) {
    const Water ib = jerlov_water("IB");
    deepsea::Setup s = parse_setup("water:\n  preset: jerlov:IB\n", "w.yaml");
    EXPECT_EQ(s.water->name, ib.name);
    EXPECT_EQ(s.water->c.r, ib.c.r);
    EXPECT_EQ(s.water->b.g, ib.b.g);
    EXPECT_EQ(s.water->phase.kind, ib.phase.kind);
    EXPECT_FALSE(s.water->forward.enabled);

    // New c on a preset keeps the preset's albedo b/c.
    s = parse_setup(
        "water:\n  preset: jerlov:IB\n  name: x\n  attenuation: [1, 1, 1]\n  phase: isotropic\n",
        "w.yaml");
    EXPECT_EQ(s.water->name, "x");
    EXPECT_EQ(s.water->c.g, 1.0);
    EXPECT_NEAR(s.water->b.g, ib.b.g / ib.c.g, 1e-15);
    EXPECT_EQ(s.water->phase.kind, PhaseKind::Isotropic);

    s = parse_setup(
        "water:\n  preset: jerlov:3C\n  scattering: [0.1, 0.1, 0.1]\n"
        "  forward_scatter: on\n",
        "w.yaml");
    EXPECT_TRUE(s.water->forward.enabled);  // on: the phase function's point spread
    EXPECT_EQ(s.water->forward.model, ForwardModel::PhaseFunction);
    s = parse_setup(
        "water:\n  preset: jerlov:3C\n  forward_scatter: {G: [0.3, 0.2, 0.2], k: 0.01}\n",
        "w.yaml");
    EXPECT_EQ(s.water->forward.model, ForwardModel::JaffeMcGlamery);  // as in the paper
    EXPECT_EQ(s.water->forward.G.g, 0.2);
    EXPECT_EQ(s.water->forward.k, 0.01);

    // The deep-ocean presets resolve like the Jerlov ones.
    s = parse_setup("water:\n  preset: deep:nepheloid\n", "w.yaml");
    EXPECT_EQ(s.water->name, "deep-nepheloid");
    EXPECT_EQ(s.water->c.g, deep_ocean_water("nepheloid").c.g);
    EXPECT_EQ(s.water->phase.kind, deep_ocean_water("nepheloid").phase.kind);

    // Without a preset: name "custom", Petzold clear, b a fixed fraction of c.
    s = parse_setup("water:\n  attenuation: [0.5, 0.2, 0.1]\n", "w.yaml");
    EXPECT_EQ(s.water->name, "custom");
    EXPECT_EQ(s.water->phase.kind, PhaseKind::PetzoldClear);
    EXPECT_GT(s.water->b.r, 0.0);
    EXPECT_LE(s.water->b.r, s.water->c.r);
    EXPECT_NEAR(s.water->b.r / s.water->c.r, s.water->b.b / s.water->c.b, 1e-12);
}

class ConfigFiles : public test::TempFolderTest {
protected:
    std::string file(const std::string& name, const std::string& text) {
        const std::string p = path(name);
        std::ofstream(p) << text;
        return p;
    }
};

TEST_F(ConfigFiles, SectionsMergeAcrossFiles) {
    const auto split = kValid.find("rig:");
    const std::string a = file("camera.yaml", kValid.substr(0, split));
    const std::string b = file("rigwater.yaml", kValid.substr(split));
    const deepsea::Setup s = load_setup({a, b});
    ASSERT_TRUE(s.camera && s.rig && s.water);
    EXPECT_EQ(s.rig->lights.size(), 2u);
    EXPECT_NO_THROW(require_complete(s, "test"));
    EXPECT_THROW(require_complete(load_setup({a}), "test"), ConfigError);
}

TEST_F(ConfigFiles, RepeatedSectionIsAnError) {
    const auto split = kValid.find("rig:");
    const std::string a = file("a.yaml", kValid.substr(0, split));
    const std::string b = file("b.yaml", "# comment\n" + kValid);
    try {
        load_setup({a, b});
        FAIL();
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind(b + ":2: camera: ", 0), 0u) << msg;
        EXPECT_NE(msg.find(a), std::string::npos) << msg;
    }
}

TEST_F(ConfigFiles, ErrorsInFilesNameTheFile) {
    const std::string bad = file("bad.yaml", replaced(kValid, "  fx: 600.0", "  fx: -3"));
    try {
        load_setup({bad});
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(bad + ":4: camera.fx: ", 0), 0u) << e.what();
    }
    try {
        load_setup({(dir_ / "missing.yaml").string()});
        FAIL();
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.yaml"), std::string::npos);
    }
}

TEST_F(ConfigFiles, LoadWater) {
    EXPECT_EQ(load_water("jerlov:II").name, jerlov_water("II").name);
    EXPECT_THROW(load_water("jerlov:XX"), ConfigError);
    EXPECT_EQ(load_water("deep:clear").c.b, deep_ocean_water("clear").c.b);
    try {
        load_water("deep:murky");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("deep:moderate"), std::string::npos) << e.what();
    }
    // The shipped water files name the presets they wrap.
    EXPECT_EQ(load_water(DEEPSEA_SOURCE_DIR "/volumes/waters/deep-clear.yaml").c.r,
              deep_ocean_water("clear").c.r);
    const std::string w = file("w.yaml", "water:\n  preset: jerlov:1C\n  name: deep\n");
    EXPECT_EQ(load_water(w).name, "deep");
    const std::string full = file("full.yaml", kValid);
    try {
        load_water(full);
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(full + ":1: camera: ", 0), 0u) << e.what();
    }
    EXPECT_THROW(load_water((dir_ / "none.yaml").string()), IoError);
}

void expect_same(const deepsea::Setup& a, const deepsea::Setup& b) {
    ASSERT_TRUE(a.camera && b.camera && a.rig && b.rig && a.water && b.water);
    EXPECT_TRUE(*a.camera == *b.camera);
    EXPECT_EQ(a.camera->fx, b.camera->fx);
    EXPECT_EQ(a.rig->name, b.rig->name);
    ASSERT_EQ(a.rig->lights.size(), b.rig->lights.size());
    for (std::size_t i = 0; i < a.rig->lights.size(); ++i) {
        const Light &x = a.rig->lights[i], &y = b.rig->lights[i];
        EXPECT_EQ(x.name, y.name);
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(x.position[k], y.position[k]);
            EXPECT_EQ(x.direction[k], y.direction[k]);
            EXPECT_EQ(x.intensity[k], y.intensity[k]);
        }
        EXPECT_EQ(x.rid.kind, y.rid.kind);
        EXPECT_EQ(x.rid.sigma_deg, y.rid.sigma_deg);
        EXPECT_EQ(x.rid.angle_deg, y.rid.angle_deg);
        EXPECT_EQ(x.rid.value, y.rid.value);
        EXPECT_EQ(x.rid.cutoff_deg, y.rid.cutoff_deg);
    }
    const Water &w = *a.water, &v = *b.water;
    EXPECT_EQ(w.name, v.name);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(w.c[k], v.c[k]);
        EXPECT_EQ(w.b[k], v.b[k]);
        EXPECT_EQ(w.forward.G[k], v.forward.G[k]);
    }
    EXPECT_EQ(w.phase.kind, v.phase.kind);
    EXPECT_EQ(w.phase.g, v.phase.g);
    EXPECT_EQ(w.forward.enabled, v.forward.enabled);
    EXPECT_EQ(w.forward.k, v.forward.k);
}

TEST(Config, SetupToYamlRoundTrips) {
    const deepsea::Setup s = parse_setup(kValid, "cfg.yaml");
    const std::string yaml = setup_to_yaml(s);
    expect_same(s, parse_setup(yaml, "round.yaml"));

    // A preset water with default forward scatter, odd names and values.
    deepsea::Setup t =
        parse_setup(kValid.substr(0, kValid.find("water:")) +
                        "water:\n  preset: jerlov:5C\n  name: \"odd: \\\"name\\\"\"\n"
                        "  phase: {petzold: turbid}\n  forward_scatter: on\n",
                    "cfg.yaml");
    t.rig->name = "";
    t.camera->cx = 0.1 + 0.2;
    t.rig->lights[0].name = "a # b";
    expect_same(t, parse_setup(setup_to_yaml(t), "round.yaml"));

    t.water->phase = Phase{PhaseKind::Isotropic, 0.0};
    t.water->forward = ForwardScatter{};
    expect_same(t, parse_setup(setup_to_yaml(t), "round.yaml"));
}

}  // namespace
TEST(Config, LampRadiusIsOptionalRangedAndWrittenBack) {
    const std::string with =
        replaced(kValid, "      cutoff_deg: 90\n", "      cutoff_deg: 90\n      radius: 0.1\n");
    const deepsea::Setup s = parse_setup(with, "r.yaml");
    EXPECT_EQ(s.rig->lights[0].radius, 0.1);
    EXPECT_EQ(s.rig->lights[1].radius, kDefaultLampRadius);  // none given
    const deepsea::Setup back = parse_setup(setup_to_yaml(s), "round.yaml");
    EXPECT_EQ(back.rig->lights[0].radius, 0.1);
    EXPECT_EQ(back.rig->lights[1].radius, kDefaultLampRadius);
    for (const char* bad : {"-0.01", "0.6"}) {
        try {
            parse_setup(replaced(with, "radius: 0.1", std::string("radius: ") + bad), "r.yaml");
            ADD_FAILURE() << bad;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("rig.lights[0].radius"), std::string::npos)
                << e.what();
        }
    }
}

}  // namespace deepsea
