#include "deepsea/batch/frame_jobs.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../temp_folder.h"
#include "deepsea/core/error.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

class FrameJobsTest : public test::TempFolderTest {
protected:
    void touch(const std::string& name) {
        fs::create_directories(fs::path(path(name)).parent_path());
        std::ofstream(path(name)) << "x";
    }
};

/// The message of the InputError that pair_frames throws.
std::string pairing_error(const std::vector<std::string>& rgb,
                          const std::vector<std::string>& depth, const std::string& rgb_pattern,
                          const std::string& depth_pattern) {
    try {
        pair_frames(rgb, depth, rgb_pattern, depth_pattern);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(PairFrames, ByNameLessThePatternsFixedText) {
    const auto jobs = pair_frames({"d/b.png", "d/a.png"}, {"d/b_depth.exr", "d/a_depth.exr"},
                                  "d/*.png", "d/*_depth.exr");
    ASSERT_EQ(jobs.size(), 2u);
    EXPECT_EQ(jobs[0].rgb, "d/a.png");
    EXPECT_EQ(jobs[0].depth, "d/a_depth.exr");
    EXPECT_EQ(jobs[1].depth, "d/b_depth.exr");
    // Prefixes count too (rgb_x / depth_x: frame x); files caught by both patterns are depth
    // files.
    const auto pre = pair_frames({"rgb_x.png"}, {"depth_x.png"}, "rgb_*.png", "depth_*.png");
    ASSERT_EQ(pre.size(), 1u);
    EXPECT_EQ(pre[0].depth, "depth_x.png");
    const auto both =
        pair_frames({"x.png", "x_depth.png"}, {"x_depth.png"}, "*.png", "*_depth.png");
    ASSERT_EQ(both.size(), 1u);
    EXPECT_EQ(both[0].rgb, "x.png");
}

TEST_F(FrameJobsTest, FrameNumberPatternsMeanTheNumberedFilesThatExist) {
    for (const char* f : {"in/frame_0001.png", "in/frame_0002.png", "in/frame_12345.png",
                          "in/frame_01.png", "in/frame_x001.png", "in/frame_0001_depth.exr",
                          "in/frame_0002_depth.exr", "in/frame_12345_depth.exr"})
        touch(f);
    const std::vector<std::string> four = {path("in/frame_0001.png"), path("in/frame_0002.png"),
                                           path("in/frame_12345.png")};
    EXPECT_EQ(glob_files(path("in/frame_%04d.png")), four);  // at least 4 digits, as printf
    EXPECT_EQ(glob_files(path("in/frame_####.png")), four);
    EXPECT_EQ(glob_files(path("in/frame_%d.png")).size(), 4u);  // 01 too, not x001
    EXPECT_TRUE(is_pattern("in/frame_%04d.png") && is_pattern("in/frame_####.png"));
    EXPECT_FALSE(is_pattern("in/frame_%04x.png"));
    touch("in/a#1.png");  // an existing file is a file, whatever its name holds
    EXPECT_FALSE(is_pattern(path("in/a#1.png")));
    // They pair by name as '*' does: frame_%04d with frame_%04d_depth.
    const auto jobs = pair_frames(glob_files(path("in/frame_####.png")),
                                  glob_files(path("in/frame_%04d_depth.exr")),
                                  path("in/frame_####.png"), path("in/frame_%04d_depth.exr"));
    ASSERT_EQ(jobs.size(), 3u);
    EXPECT_EQ(jobs[2].depth, path("in/frame_12345_depth.exr"));
    // Glob characters keep their meaning beside them; regex characters are plain text.
    touch("in/b+(1)[x].png");
    EXPECT_EQ(glob_files(path("in/b+(%d)[[]x].png")).size(), 1u);
    EXPECT_EQ(glob_files(path("in/?rame_%04d.png")), four);
}

TEST(PairFrames, ByNumberWhereTheNamesDiffer) {
    const auto jobs = pair_frames({"c/0001.png", "c/0002.png", "c/0010.png"},
                                  {"z/d_10.exr", "z/d_2.exr", "z/d_1.exr"}, "c/*.png", "z/*.exr");
    ASSERT_EQ(jobs.size(), 3u);
    EXPECT_EQ(jobs[0].depth, "z/d_1.exr");
    EXPECT_EQ(jobs[1].depth, "z/d_2.exr");
    EXPECT_EQ(jobs[2].depth, "z/d_10.exr");  // not by sorted position (d_10 < d_2)
}

TEST(PairFrames, AMissingFileIsAnErrorListingTheUnpairedOnes) {
    // Formerly paired by position: frame 2 got frame 3's depth.
    const std::string e = pairing_error({"f1.png", "f2.png", "f3.png"},
                                        {"f1_depth.exr", "f3_depth.exr"}, "*.png", "*_depth.exr");
    EXPECT_NE(e.find("1 colour file(s) without depth"), std::string::npos) << e;
    EXPECT_NE(e.find("f2.png"), std::string::npos) << e;
    EXPECT_EQ(e.find("f3.png"), std::string::npos) << e;
    const std::string both = pairing_error({"f1.png", "f2.png"}, {"f1_depth.exr", "f7_depth.exr"},
                                           "*.png", "*_depth.exr");
    EXPECT_NE(both.find("f2.png"), std::string::npos) << both;
    EXPECT_NE(both.find("1 depth file(s) without colour"), std::string::npos) << both;
    EXPECT_NE(both.find("f7_depth.exr"), std::string::npos) << both;
    EXPECT_THROW(pair_frames({}, {"a_depth.exr"}, "*.png", "*_depth.exr"), InputError);
    EXPECT_THROW(pair_frames({"a.png"}, {}, "*.png", "*_depth.exr"), InputError);
}

TEST(PairFrames, TwoFilesOfOneFrameAreAnError) {
    const std::string e = pairing_error({"a/1.png", "b/1.png"}, {"a/1_depth.exr", "b/1_depth.exr"},
                                        "*/*.png", "*/*_depth.exr");
    EXPECT_NE(e.find("are both frame '1'"), std::string::npos) << e;
}

TEST_F(FrameJobsTest, OneFrameOrEveryPairOfTwoPatterns) {
    for (const char* f : {"in/f2.png", "in/f1.png", "in/f1_depth.exr", "in/f2_depth.exr"}) touch(f);

    const auto one =
        frame_jobs({path("in/f1.png"), path("in/f1_depth.exr"), path("o.png"), "", ""});
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0].output, path("o.png"));
    EXPECT_TRUE(one[0].layers.empty());
    EXPECT_THROW(frame_jobs({"a.png", path("in/*.exr"), "out.png", "", ""}), ConfigError);

    // '*.png' does not catch the depth files here, 'f*' does: both pair the same frames.
    for (const char* pattern : {"*.png", "f*"}) {
        const auto jobs = frame_jobs({(dir_ / "in" / pattern).string(), path("in/*_depth.exr"),
                                      path("out"), path("layers"), ""});
        ASSERT_EQ(jobs.size(), 2u) << pattern;
        EXPECT_EQ(jobs[1].rgb, path("in/f2.png"));
        EXPECT_EQ(jobs[1].depth, path("in/f2_depth.exr"));
        EXPECT_EQ(jobs[1].output, path("out/f2.png"));
        EXPECT_EQ(jobs[1].layers, path("layers/f2.exr"));
    }
    // Checking creates nothing: the folders come later (OutputFolders).
    EXPECT_FALSE(fs::exists(path("out")) || fs::exists(path("layers")));
    EXPECT_THROW(frame_jobs({path("in/*.jpg"), path("in/*.exr"), path("out"), "", ""}), InputError);
}

TEST_F(FrameJobsTest, OutputsNeverOverwriteInputsOrEachOther) {
    for (const char* f : {"in/f1.png", "in/f1_depth.exr"}) touch(f);
    const std::string rgb = path("in/f1.png"), depth = path("in/f1_depth.exr");
    EXPECT_THROW(frame_jobs({rgb, depth, rgb, "", ""}), ConfigError);
    EXPECT_THROW(frame_jobs({rgb, depth, "", depth, ""}), ConfigError);
    EXPECT_THROW(frame_jobs({rgb, depth, path("in/../in/f1.png"), "", ""}), ConfigError);
    EXPECT_THROW(frame_jobs({rgb, depth, path("x.exr"), path("x.exr"), ""}), ConfigError);
    EXPECT_THROW(frame_jobs({rgb, depth, "", "", ""}), ConfigError);  // nothing to write
    EXPECT_THROW(frame_jobs({path("in/*.png"), path("in/*_depth.exr"), path("in"), "", ""}),
                 ConfigError);
    EXPECT_THROW(frame_jobs({path("in/*.png"), path("in/*_depth.exr"), "", path("in/."), ""}),
                 ConfigError);
}

TEST_F(FrameJobsTest, OutputNamesAndFoldersAreCheckedFirst) {
    for (const char* f : {"in/f1.png", "in/f1_depth.exr"}) touch(f);
    const std::string rgb = path("in/f1.png"), depth = path("in/f1_depth.exr");
    EXPECT_THROW(frame_jobs({rgb, depth, path("x.unknown"), "", ""}), IoError);
    EXPECT_THROW(frame_jobs({rgb, depth, path("noext"), "", ""}), IoError);
    EXPECT_THROW(frame_jobs({rgb, depth, "", path("layers.png"), ""}), ConfigError);
    EXPECT_THROW(frame_jobs({rgb, depth, path("missing/x.png"), "", ""}), IoError);
    EXPECT_NO_THROW(frame_jobs({rgb, depth, path("x.exr"), path("l.EXR"), ""}));
    const std::string seq = path("in/*.png"), seq_depth = path("in/*_depth.exr");
    EXPECT_THROW(frame_jobs({seq, seq_depth, path("frames.png"), "", ""}), ConfigError);
    EXPECT_THROW(frame_jobs({seq, seq_depth, rgb, "", ""}), ConfigError);  // an existing file
    EXPECT_THROW(frame_jobs({seq, seq_depth, path("in/f1.png/sub"), "", ""}), IoError);
    EXPECT_NO_THROW(frame_jobs({seq, seq_depth, path("new/deeper/out"), path("new/out"), ""}));
    EXPECT_TRUE(listing().size() == 1u);  // only in/
}

TEST_F(FrameJobsTest, FormatNamesTheSequencesImagesAndMustMatchOneFramesOutput) {
    for (const char* f : {"in/f1.png", "in/f1_depth.exr"}) touch(f);
    const std::string seq = path("in/*.png"), seq_depth = path("in/*_depth.exr");
    for (const char* format : {"jpg", "tif", "exr", "png"}) {
        const auto jobs = frame_jobs({seq, seq_depth, path("out"), "", format});
        ASSERT_EQ(jobs.size(), 1u);
        EXPECT_EQ(jobs[0].output, path(std::string("out/f1.") + format));
    }
    EXPECT_EQ(frame_jobs({seq, seq_depth, path("out"), "", ""})[0].output, path("out/f1.png"));
    EXPECT_THROW(frame_jobs({seq, seq_depth, path("out"), "", "bmp"}), ConfigError);
    const std::string rgb = path("in/f1.png"), depth = path("in/f1_depth.exr");
    EXPECT_NO_THROW(frame_jobs({rgb, depth, path("x.JPEG"), "", "jpg"}));
    EXPECT_NO_THROW(frame_jobs({rgb, depth, path("x.jpg"), "", ""}));
    try {
        frame_jobs({rgb, depth, path("x.png"), "", "jpg"});
        ADD_FAILURE() << "-o x.png with --format jpg was accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("x.png: -o is not a .jpg file but --format is jpg"),
                  std::string::npos)
            << e.what();
    }
}

TEST_F(FrameJobsTest, OutputFoldersAreComparedAsTheSystemResolvesThem) {
    for (const char* f : {"in/f1.png", "in/f1_depth.exr", "in/f2.png", "in/f2_depth.exr"}) touch(f);
    fs::create_directory_symlink(path("in"), path("in-link"));
    const std::string seq = path("in/*.png"), seq_depth = path("in/*_depth.exr");
    // Missing components before "..": the kernel reaches in/ once they are made.
    for (const std::string o : {"in/nosuch/..", "in/a/b/../..", "in/x/../", "in/", "in-link",
                                "in-link/y/..", "f1.png/../in-link", "nosuch/../in-link/"}) {
        EXPECT_THROW(frame_jobs({seq, seq_depth, path(o), "", ""}), ConfigError) << o;
        EXPECT_THROW(frame_jobs({seq, seq_depth, "", path(o), ""}), ConfigError) << o;
    }
    // The same from the working folder, with relative names.
    const fs::path cwd = fs::current_path();
    fs::current_path(dir_);
    EXPECT_THROW(frame_jobs({"in/*.png", "in/*_depth.exr", "./in/x/../", "", ""}), ConfigError);
    EXPECT_THROW(frame_jobs({"./in/f1.png", "in/f1_depth.exr", "in/nosuch/../f1.png", "", ""}),
                 ConfigError);
    EXPECT_NO_THROW(frame_jobs({"in/*.png", "in/*_depth.exr", "in/nosuch", "", ""}));
    fs::current_path(cwd);
    EXPECT_NO_THROW(frame_jobs({seq, seq_depth, path("in/sub"), "", ""}));
    EXPECT_EQ(listing().size(), 2u);  // in/ and in-link: nothing made
}

TEST_F(FrameJobsTest, AnOutputThatIsAnInputUnderAnotherNameIsRefused) {
    for (const char* f : {"in/f1.png", "in/f1_depth.exr", "in/f2.png", "in/f2_depth.exr"}) touch(f);
    fs::create_directories(path("out"));
    // A link in the output folder to another frame's input, and a hard link to a depth file.
    fs::create_symlink(path("in/f1.png"), path("out/f2.png"));
    const std::string seq = path("in/*.png"), seq_depth = path("in/*_depth.exr");
    EXPECT_THROW(frame_jobs({seq, seq_depth, path("out"), "", ""}), ConfigError);
    fs::remove(path("out/f2.png"));
    EXPECT_NO_THROW(frame_jobs({seq, seq_depth, path("out"), "", ""}));
    fs::create_directories(path("layers"));
    fs::create_hard_link(path("in/f2_depth.exr"), path("layers/f1.exr"));
    EXPECT_THROW(frame_jobs({seq, seq_depth, "", path("layers"), ""}), ConfigError);
    fs::create_symlink(path("in/f1.png"), path("one.png"));
    EXPECT_THROW(frame_jobs({path("in/f1.png"), path("in/f1_depth.exr"), path("one.png"), "", ""}),
                 ConfigError);
}

}  // namespace deepsea
