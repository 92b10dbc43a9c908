// The camera section's `port` key (src/io/port_config.cpp; docs/config.md, docs/ports.md):
// what it parses to, its defaults, the errors at the key's line, and the round trip through
// setup_to_yaml.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../message_of.h"
#include "../replaced.h"
#include "../temp_folder.h"
#include "deepsea/core/error.h"
#include "deepsea/io/config.h"

namespace deepsea {
namespace {

// Line numbers matter: the error tests below refer to them.
const std::string kFlat =
    "camera:\n"                               // 1
    "  width: 320\n"                          // 2
    "  height: 240\n"                         // 3
    "  fx: 300.0\n"                           // 4
    "  fy: 300.0\n"                           // 5
    "  cx: 159.5\n"                           // 6
    "  cy: 119.5\n"                           // 7
    "  port:\n"                               // 8
    "    flat:\n"                             // 9
    "      normal: [0.02, 0, 1]\n"            // 10
    "      distance: 0.015\n"                 // 11
    "      glass_thickness: 0.01\n"           // 12
    "      n_glass: 1.52\n"                   // 13
    "      n_water: [1.339, 1.342, 1.347]\n"  // 14
    "    fresnel: true\n";                    // 15

const std::string kDome =
    "camera:\n"                               // 1
    "  width: 320\n"                          // 2
    "  height: 240\n"                         // 3
    "  fx: 300.0\n"                           // 4
    "  fy: 300.0\n"                           // 5
    "  cx: 159.5\n"                           // 6
    "  cy: 119.5\n"                           // 7
    "  port:\n"                               // 8
    "    dome:\n"                             // 9
    "      centre: [0.001, -0.002, 0.003]\n"  // 10
    "      radius: 0.05\n"                    // 11
    "      glass_thickness: 0.007\n"          // 12
    "      n_water: 1.343\n";                 // 13

using test::replaced;

std::string error_of(const std::string& text) {
    return test::message_of<ConfigError>([&] { parse_setup(text, "cam.yaml"); });
}

TEST(PortConfig, KeysParseIntoThePort) {
    const deepsea::Setup s = parse_setup(kFlat, "cam.yaml");
    ASSERT_TRUE(s.camera && s.port);
    EXPECT_FALSE(s.camera_model);  // a port alone makes no camera stage
    const Port& p = *s.port;
    EXPECT_EQ(p.kind, PortKind::Flat);
    EXPECT_EQ(p.flat.normal.x, 0.02);  // as written: normalised where used
    EXPECT_EQ(p.flat.distance, 0.015);
    EXPECT_EQ(p.flat.glass_thickness, 0.01);
    EXPECT_EQ(p.n_air, 1.0);  // the default
    EXPECT_EQ(p.n_glass, 1.52);
    EXPECT_EQ(p.n_water.b, 1.347);
    EXPECT_TRUE(p.dispersive());
    EXPECT_TRUE(p.fresnel);

    const deepsea::Setup d = parse_setup(kDome, "cam.yaml");
    ASSERT_TRUE(d.port);
    EXPECT_EQ(d.port->kind, PortKind::Dome);
    EXPECT_EQ(d.port->dome.centre.y, -0.002);
    EXPECT_EQ(d.port->dome.radius, 0.05);
    EXPECT_EQ(d.port->dome.glass_thickness, 0.007);
    EXPECT_EQ(d.port->n_glass, Port().n_glass);
    EXPECT_EQ(d.port->n_water.r, 1.343);  // one number: every channel
    EXPECT_FALSE(d.port->dispersive());
    EXPECT_FALSE(d.port->fresnel);
    // Without the key: no port.
    EXPECT_FALSE(parse_setup(kFlat.substr(0, kFlat.find("  port:")), "cam.yaml").port);
    // The defaults of the optional keys: normal along the axis, dome centred.
    const deepsea::Setup m =
        parse_setup(replaced(kDome, "      centre: [0.001, -0.002, 0.003]\n", ""), "c");
    EXPECT_EQ(m.port->dome.centre.z, 0.0);
    const deepsea::Setup f = parse_setup(replaced(kFlat, "      normal: [0.02, 0, 1]\n", ""), "c");
    EXPECT_EQ(f.port->flat.normal.z, 1.0);
    EXPECT_EQ(f.port->flat.normal.x, 0.0);
}

TEST(PortConfig, BadValuesNameFileLineAndKey) {
    struct Bad {
        std::string text, from, to, expect;
    };
    const Bad cases[] = {
        {kFlat, "glass_thickness: 0.01", "glass_thickness: 0",
         "cam.yaml:12: camera.port.flat.glass_thickness: must be > 0, got 0"},
        {kFlat, "distance: 0.015", "distance: -0.01",
         "cam.yaml:11: camera.port.flat.distance: must be >= 0, got -0.01"},
        {kFlat, "n_glass: 1.52", "n_glass: 0",
         "cam.yaml:13: camera.port.flat.n_glass: must be > 0 and finite, got 0"},
        {kFlat, "[1.339, 1.342, 1.347]", "[1.339, -1, 1.347]",
         "cam.yaml:14: camera.port.flat.n_water: must be > 0 and finite (G is -1)"},
        {kFlat, "[0.02, 0, 1]", "[0, 0, 0]",
         "cam.yaml:10: camera.port.flat.normal: must be a non-zero vector of finite length"},
        {kFlat, "[0.02, 0, 1]", "[0, 0, -1]",
         "cam.yaml:10: camera.port.flat.normal: the interface is behind the camera for the ray "
         "through image point (u, v) = "},
        {kFlat, "[1.339, 1.342, 1.347]", "0.5",
         "cam.yaml:14: camera.port.flat.n_water: total internal reflection at the outer "
         "surface"},
        {kFlat, "[1.339, 1.342, 1.347]", "[1, 2]",
         "cam.yaml:14: camera.port.flat.n_water: expected a list of 3 numbers"},
        {kFlat, "    fresnel: true", "    fresnel: 1.5", "cam.yaml:15: camera.port.fresnel:"},
        {kFlat, "      n_glass: 1.52", "      n_glas: 1.52",
         "cam.yaml:13: camera.port.flat.n_glas: unknown key (expected normal, distance, "
         "glass_thickness, n_air, n_glass, n_water)"},
        {kFlat, "      distance: 0.015\n", "", "cam.yaml:9: camera.port.flat.distance: missing"},
        {kDome, "centre: [0.001, -0.002, 0.003]", "centre: [0, 0, 0.06]",
         "cam.yaml:10: camera.port.dome.centre: puts the camera centre outside the dome: "
         "|centre| = 0.06 m >= radius = 0.05 m"},
        {kDome, "radius: 0.05", "radius: 0", "cam.yaml:11: camera.port.dome.radius: must be > 0"},
        {kDome, "radius: 0.05", "radius: \"0.05\"",
         "cam.yaml:11: camera.port.dome.radius: expected a number"},
        {kDome, "    dome:\n", "    cone:\n", "cam.yaml:9: camera.port.cone: unknown key"},
    };
    for (const Bad& c : cases) {
        const std::string e = error_of(replaced(c.text, c.from, c.to));
        EXPECT_EQ(e.rfind(c.expect, 0), 0u) << "got: " << e << "\nexpected: " << c.expect;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
    // Both models, or neither, at the port's line.
    const std::string both =
        kDome.substr(0, kDome.find("    dome:")) +
        "    flat: {distance: 0.01, glass_thickness: 0.01}\n    dome: {radius: 1, "
        "glass_thickness: 0.01}\n";
    EXPECT_EQ(error_of(both), "cam.yaml:8: camera.port: give exactly one of flat, dome");
    EXPECT_EQ(error_of(kDome.substr(0, kDome.find("    dome:")) + "    fresnel: true\n"),
              "cam.yaml:8: camera.port: give exactly one of flat, dome");
}

TEST(PortConfig, SetupToYamlRoundTrips) {
    for (const std::string& text : {kFlat, kDome}) {
        const deepsea::Setup s = parse_setup(text, "cam.yaml");
        const std::string yaml = setup_to_yaml(s);
        const deepsea::Setup t = parse_setup(yaml, "round.yaml");
        ASSERT_TRUE(t.port) << yaml;
        const Port &a = *s.port, &b = *t.port;
        EXPECT_EQ(a.kind, b.kind);
        for (int i = 0; i < 3; ++i) {
            EXPECT_EQ(a.flat.normal[i], b.flat.normal[i]);
            EXPECT_EQ(a.dome.centre[i], b.dome.centre[i]);
            EXPECT_EQ(a.n_water[i], b.n_water[i]);
        }
        EXPECT_EQ(a.flat.distance, b.flat.distance);
        EXPECT_EQ(a.flat.glass_thickness, b.flat.glass_thickness);
        EXPECT_EQ(a.dome.radius, b.dome.radius);
        EXPECT_EQ(a.dome.glass_thickness, b.dome.glass_thickness);
        EXPECT_EQ(a.n_air, b.n_air);
        EXPECT_EQ(a.n_glass, b.n_glass);
        EXPECT_EQ(a.fresnel, b.fresnel);
        EXPECT_EQ(setup_to_yaml(t), yaml);  // and writes the same text again
    }
    // A camera section without a port writes none.
    deepsea::Setup plain = parse_setup(kFlat, "cam.yaml");
    plain.port.reset();
    EXPECT_EQ(setup_to_yaml(plain).find("port:"), std::string::npos);
}

class PortFiles : public test::TempFolderTest {};

TEST_F(PortFiles, ThePortComesWithTheCameraSection) {
    // load_setup merges files: the port is the camera section's, as its camera stage is.
    const std::string cam = path("cam.yaml"), water = path("water.yaml");
    std::ofstream(cam) << kDome;
    std::ofstream(water) << "water: {preset: 'jerlov:IB'}\n";
    const deepsea::Setup s = load_setup({water, cam});
    ASSERT_TRUE(s.port && s.water);
    EXPECT_EQ(s.port->dome.radius, 0.05);
}

TEST(PortConfig, CommandsThatWouldIgnoreThePortRefuseIt) {
    // A complete setup may hold a port (bake, demo and render work through one); a command that
    // cannot (reference, bench) refuses it naming the key and what is not built, never silently
    // ignoring it.
    deepsea::Setup s = parse_setup(kFlat, "cam.yaml");
    s.rig = Rig{};
    s.water = Water{};
    EXPECT_NO_THROW(require_complete(s, "deepsea bake"));
    try {
        refuse_port(s, "deepsea reference", "the reference through a port is not built");
        FAIL() << "a port was accepted";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("deepsea reference: camera.port: the reference "
                                              "through a port is not built, and this command "
                                              "would ignore the port",
                                              0),
                  0u)
            << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
    s.port.reset();
    EXPECT_NO_THROW(refuse_port(s, "deepsea reference", "not built"));
}

}  // namespace
}  // namespace deepsea
