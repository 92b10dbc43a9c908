// The strict reader on its own (src/io/yaml_reader.h, private to io): where each kind of error
// is reported. The camera / rig / water schema on top of it is config_test.cpp.
#include "yaml_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../message_of.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/schema.h"

namespace deepsea::yaml {
namespace {

/// The message of the ConfigError that f throws ("" if none).
template <class F>
std::string error_of(F f) {
    return test::message_of<ConfigError>(f);
}

bool starts_with(const std::string& s, const std::string& prefix) {
    return s.rfind(prefix, 0) == 0;
}

const std::string kText =
    "a:\n"           // 1
    "  x: 1.5\n"     // 2
    "  n: 3\n"       // 3
    "  s: \"7\"\n"   // 4
    "  v: [1, 2]\n"  // 5
    "  on: true\n"   // 6
    "b: [4, x]\n";   // 7

TEST(YamlReader, TypedGettersNameFileLineAndKey) {
    const Document doc(kText, "f.yaml");
    const MapView top(doc, doc.root(), std::vector<std::string>{"a", "b"});
    const MapView a(doc, top.need("a"), std::vector<std::string>{"x", "n", "s", "v", "on"});
    EXPECT_EQ(doc.number(a.need("x")), 1.5);
    EXPECT_EQ(doc.integer(a.need("n")), 3);
    EXPECT_TRUE(doc.boolean(a.need("on")));
    EXPECT_EQ(doc.string(a.need("s")), "7");
    EXPECT_TRUE(starts_with(error_of([&] { doc.integer(a.need("x")); }), "f.yaml:2: a.x: "));
    // A quoted number is a string: strict files do not coerce it.
    EXPECT_TRUE(starts_with(error_of([&] { doc.number(a.need("s")); }), "f.yaml:4: a.s: "));
    EXPECT_TRUE(starts_with(error_of([&] { doc.vec3(a.need("v")); }), "f.yaml:5: a.v: "));
    EXPECT_TRUE(
        starts_with(error_of([&] { doc.numbers(top.need("b"), 2, ""); }), "f.yaml:7: b[1]: "));
    EXPECT_TRUE(starts_with(error_of([&] { doc.list(a.need("x")); }), "f.yaml:2: a.x: "));
}

TEST(YamlReader, MapsRejectUnknownRepeatedAndMissingKeys) {
    const Document doc(kText, "f.yaml");
    const std::string unknown =
        error_of([&] { MapView(doc, doc.root(), std::vector<std::string>{"a"}); });
    EXPECT_TRUE(starts_with(unknown, "f.yaml:7: b: unknown key (expected a)")) << unknown;
    // Any key when no set is given (foreign formats).
    EXPECT_EQ(error_of([&] { MapView(doc, doc.root(), std::nullopt); }), "");
    const MapView top(doc, doc.root(), std::vector<std::string>{"a", "b", "c"});
    // A missing key is reported on the line of the map that should hold it.
    const MapView a(doc, top.need("a"), std::vector<std::string>{"x", "n", "s", "v", "on", "z"});
    EXPECT_TRUE(starts_with(error_of([&] { a.need("z"); }), "f.yaml:1: a.z: missing"));
    EXPECT_EQ(top.opt("c"), nullptr);
    EXPECT_THROW(top.opt("not-in-the-set"), std::logic_error);
    EXPECT_EQ(top.keys(), (std::vector<std::string>{"a", "b"}));

    const Document twice("k: 1\nk: 2\n", "t.yaml");
    const std::string repeated =
        error_of([&] { MapView(twice, twice.root(), std::vector<std::string>{"k"}); });
    EXPECT_TRUE(starts_with(repeated, "t.yaml:2: k: repeated key (first given on line 1)"))
        << repeated;
}

TEST(YamlReader, SyntaxErrorsAndEmptyDocuments) {
    const std::string syntax = error_of([] { Document("a: [1\n", "s.yaml"); });
    EXPECT_TRUE(starts_with(syntax, "s.yaml:")) << syntax;
    EXPECT_NE(syntax.find("YAML syntax error"), std::string::npos) << syntax;
    EXPECT_TRUE(Document("# only a comment\n", "e.yaml").empty());
}

TEST(YamlReader, SchemaErrorsAreReportedAtTheLineOfTheirKey) {
    const std::string text =
        "rig:\n"                                  // 1
        "  lights:\n"                             // 2
        "    - intensity: [1, 2, 3]\n"            // 3
        "      rid: {table: {value: [1, 2]}}\n";  // 4
    const Document doc(text, "r.yaml");
    const MapView top(doc, doc.root(), std::nullopt);
    const MapView rig(doc, top.need("rig"), std::nullopt);
    const auto lights = doc.list(rig.need("lights"));
    const MapView light(doc, lights[0], std::nullopt);
    const MapView rid(doc, light.need("rid"), std::nullopt);
    const MapView table(doc, rid.need("table"), std::nullopt);
    doc.list(table.need("value"));
    auto at = [&](const char* key) { return error_of([&] { doc.fail(SchemaError(key, "bad")); }); };
    EXPECT_EQ(at("rig.lights[0].rid.table.value[1]"),
              "r.yaml:4: rig.lights[0].rid.table.value[1]: bad");
    // Not read (a default or derived value): the nearest enclosing value that was.
    EXPECT_EQ(at("rig.lights[0].cutoff_deg"), "r.yaml:3: rig.lights[0].cutoff_deg: bad");
    EXPECT_EQ(at("water.scattering"), "r.yaml:1: water.scattering: bad");
}

TEST(YamlReader, FilesThatCannotBeReadAreIoErrors) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("deepsea-yaml-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    EXPECT_THROW(Document::load((dir / "none.yaml").string()), IoError);
    EXPECT_THROW(Document::load(dir.string()), IoError);
    std::ofstream((dir / "ok.yaml").string()) << "k: 1\n";
    EXPECT_EQ(Document::load((dir / "ok.yaml").string()).file(), (dir / "ok.yaml").string());
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace deepsea::yaml
