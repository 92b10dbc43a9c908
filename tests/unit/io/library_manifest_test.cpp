#include "deepsea/io/library_manifest.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../message_of.h"
#include "../temp_folder.h"
#include "deepsea/core/error.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

class Manifest : public test::TempFolderTest {
protected:
    void SetUp() override {
        TempFolderTest::SetUp();
        fs::create_directories(dir_ / "rigs");
        for (const char* f : {"cam.yaml", "rigs/a.yaml", "rigs/b.yaml", "w.yaml"})
            std::ofstream((dir_ / f).string()) << "# placeholder\n";
    }
    LibraryManifest parse(const std::string& text) {
        return parse_library_manifest(text, "lib.yaml", dir_.string());
    }
    /// The ConfigError message, or "" if text parses.
    std::string error(const std::string& text) {
        return test::message_of<ConfigError>([&] { parse(text); });
    }
};

TEST_F(Manifest, ExpandsSortedUniqueCombinations) {
    const LibraryManifest m = parse(
        "cameras: [cam.yaml]\n"
        "rigs: [rigs/b.yaml, rigs/a.yaml, rigs/b.yaml]\n"
        "waters: [jerlov:IB, w.yaml]\n"
        "bake: {xy_step: 64, depth_samples: 4, z_max: 6, depth_scheme: sqrt, tolerance: 0.01}\n");
    ASSERT_EQ(m.rigs.size(), 2u);
    EXPECT_EQ(m.rigs[0], (dir_ / "rigs/a.yaml").string());
    ASSERT_EQ(m.entries.size(), 4u);
    // Sorted as strings: the resolved path (here absolute) before the jerlov: spec.
    EXPECT_EQ(m.entries[0].name, "cam__a__w.vdb");
    EXPECT_EQ(m.entries[1].name, "cam__a__jerlov-IB.vdb");
    EXPECT_EQ(m.entries[1].water, "jerlov:IB");
    EXPECT_EQ(m.entries[3].name, "cam__b__jerlov-IB.vdb");
    EXPECT_EQ(*m.bake.xy_step, 64);
    EXPECT_EQ(*m.bake.depth_samples, 4);
    EXPECT_EQ(*m.bake.z_max, "6");
    EXPECT_EQ(*m.bake.depth_scheme, "sqrt");
    EXPECT_EQ(*m.bake.tolerance, 0.01);
    const LibraryManifest plain = parse(
        "cameras: [cam.yaml]\nrigs: [rigs/a.yaml]\n"
        "waters: [jerlov:II, deep:clear]\nbake:\n");
    ASSERT_EQ(plain.entries.size(), 2u);
    EXPECT_EQ(plain.entries[0].name, "cam__a__deep-clear.vdb");
    EXPECT_FALSE(plain.bake.xy_step || plain.bake.z_max || plain.bake.tolerance);
}

TEST_F(Manifest, ErrorsNameFileLineAndKey) {
    const std::string ok = "cameras: [cam.yaml]\nrigs: [rigs/a.yaml]\nwaters: [jerlov:IB]\n";
    EXPECT_EQ(error(ok), "");
    EXPECT_EQ(error(ok + "bake: {xy_step: two}\n").rfind("lib.yaml:4: bake.xy_step: ", 0), 0u);
    EXPECT_EQ(error(ok + "bake: {xystep: 2}\n").rfind("lib.yaml:4: bake.xystep: unknown key", 0),
              0u);
    EXPECT_EQ(error(ok + "lamps: []\n").rfind("lib.yaml:4: lamps: unknown key", 0), 0u);
    EXPECT_EQ(error("cameras: [cam.yaml]\nrigs: [rigs/a.yaml]\n")
                  .rfind("lib.yaml:1: waters: missing required key", 0),
              0u);
    EXPECT_EQ(error("cameras: []\nrigs: [rigs/a.yaml]\nwaters: [jerlov:IB]\n")
                  .rfind("lib.yaml:1: cameras: expected a non-empty list", 0),
              0u);
    const std::string missing =
        error("cameras: [cam.yaml]\nrigs: [rigs/a.yaml, rigs/none.yaml]\nwaters: [jerlov:IB]\n");
    EXPECT_EQ(missing.rfind("lib.yaml:2: rigs[1]: missing file ", 0), 0u) << missing;
    EXPECT_NE(error("- cameras\n").find("not a manifest"), std::string::npos);
    const std::string preset =
        error("cameras: [cam.yaml]\nrigs: [rigs/a.yaml]\nwaters: [jerlov:IB, deep:murky]\n");
    EXPECT_EQ(preset.rfind("lib.yaml:3: waters[1]: unknown water preset 'deep:murky'", 0), 0u)
        << preset;
    // Same stem twice: both would write one asset.
    std::ofstream((dir_ / "jerlov-IB.yaml").string()) << "# placeholder\n";
    EXPECT_NE(
        error("cameras: [cam.yaml]\nrigs: [rigs/a.yaml]\nwaters: [jerlov:IB, jerlov-IB.yaml]\n")
            .find("two entries would both write cam__a__jerlov-IB.vdb"),
        std::string::npos);
}

TEST_F(Manifest, LoadResolvesPathsAgainstTheManifestsFolder) {
    const std::string path = (dir_ / "lib.yaml").string();
    std::ofstream(path) << "cameras: [cam.yaml]\nrigs: [rigs/a.yaml]\nwaters: [w.yaml]\n";
    const LibraryManifest m = load_library_manifest(path);
    ASSERT_EQ(m.entries.size(), 1u);
    EXPECT_EQ(m.entries[0].camera, (dir_ / "cam.yaml").string());
    EXPECT_THROW(load_library_manifest((dir_ / "none.yaml").string()), IoError);
}

TEST(LibraryManifestShipped, VolumesLibraryExpands) {
    const LibraryManifest m = load_library_manifest(DEEPSEA_SOURCE_DIR "/volumes/library.yaml");
    EXPECT_EQ(m.entries.size(), m.cameras.size() * m.rigs.size() * m.waters.size());
    EXPECT_FALSE(m.entries.empty());
}

}  // namespace
}  // namespace deepsea
