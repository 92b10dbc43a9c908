#include "deepsea/runtime/frame_jobs.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "deepsea/core/error.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

TEST(PairFrames, CountsMustMatch) {
    EXPECT_THROW(pair_frames({"a.png", "b.png"}, {"a_depth.exr"}, "*.png", "*_depth.exr"),
                 InputError);
    EXPECT_THROW(pair_frames({}, {"a_depth.exr"}, "*.png", "*_depth.exr"), InputError);
    const auto jobs = pair_frames({"b.png", "a.png"}, {"b_depth.exr", "a_depth.exr"}, "", "");
    ASSERT_EQ(jobs.size(), 2u);
    EXPECT_EQ(jobs[0].rgb, "a.png");
    EXPECT_EQ(jobs[0].depth, "a_depth.exr");
}

TEST(FrameJobs, OneFrameOrEveryPairOfTwoPatterns) {
    const fs::path dir = fs::temp_directory_path() / ("deepsea-jobs-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const char* f : {"f2.png", "f1.png", "f1_depth.exr", "f2_depth.exr"})
        std::ofstream((dir / f).string()) << "x";

    const auto one = frame_jobs({"a.png", "a.exr", "out.png", ""});
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0].output, "out.png");
    EXPECT_TRUE(one[0].layers.empty());
    EXPECT_THROW(frame_jobs({"a.png", (dir / "*.exr").string(), "out.png", ""}), ConfigError);

    // '*.png' does not catch the depth files here, 'f*' does: both are paired by position.
    for (const char* pattern : {"*.png", "f*"}) {
        const auto jobs = frame_jobs({(dir / pattern).string(), (dir / "*_depth.exr").string(),
                                      (dir / "out").string(), (dir / "layers").string()});
        ASSERT_EQ(jobs.size(), 2u) << pattern;
        EXPECT_EQ(jobs[1].rgb, (dir / "f2.png").string());
        EXPECT_EQ(jobs[1].depth, (dir / "f2_depth.exr").string());
        EXPECT_EQ(jobs[1].output, (dir / "out" / "f2.png").string());
        EXPECT_EQ(jobs[1].layers, (dir / "layers" / "f2.exr").string());
        EXPECT_TRUE(fs::is_directory(dir / "out") && fs::is_directory(dir / "layers"));
    }
    EXPECT_THROW(frame_jobs({(dir / "*.jpg").string(), (dir / "*.exr").string(), "", ""}),
                 InputError);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace deepsea
