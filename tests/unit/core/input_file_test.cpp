#include "deepsea/core/input_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "../message_of.h"
#include "../temp_folder.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

class InputFile : public test::TempFolderTest {};

/// The IoError's message of f(), or "" if it throws none.
template <typename F>
std::string io_error(F f) {
    return test::message_of<IoError>(f);
}

}  // namespace

TEST_F(InputFile, ReadsARegularFile) {
    std::ofstream(path("a.yaml")) << "camera: {}\n";
    EXPECT_EQ(read_text_file(path("a.yaml"), "a YAML file"), "camera: {}\n");
    fs::create_symlink(path("a.yaml"), path("link.yaml"));
    EXPECT_EQ(read_text_file(path("link.yaml"), "a YAML file"), "camera: {}\n");
}

TEST_F(InputFile, DevicesPipesFoldersAndHugeFilesAreRefusedBeforeReading) {
    const auto t0 = std::chrono::steady_clock::now();
    if (fs::exists("/dev/zero")) {
        EXPECT_EQ(io_error([] { (void)read_text_file("/dev/zero", "a YAML file"); }),
                  "/dev/zero: is not a regular file (a device, pipe or socket); deepsea reads "
                  "a YAML file only from a file");
    }
    ASSERT_EQ(::mkfifo(path("pipe").c_str(), 0644), 0);  // opening it would wait for a writer
    EXPECT_NE(io_error([&] {
                  (void)read_text_file(path("pipe"), "a manifest");
              }).find("not a regular file"),
              std::string::npos);
    EXPECT_EQ(io_error([&] { (void)read_text_file(dir_.string(), "a YAML file"); }),
              dir_.string() + ": is a folder, not a YAML file");
    EXPECT_EQ(io_error([&] { (void)read_text_file(path("none"), "a YAML file"); }),
              path("none") + ": no such file");
    std::ofstream(path("big")) << std::string(3 << 20, 'x');
    EXPECT_NE(io_error([&] {
                  (void)read_text_file(path("big"), "a YAML file", 1 << 20);
              }).find("3 MB, larger than deepsea reads for a YAML file (at most 1 MB)"),
              std::string::npos);
    EXPECT_NE(io_error([] { require_input_file("", 10, "an image"); }), "");
    EXPECT_NE(
        io_error([&] { require_input_file(std::string("a\0b", 3), 10, "an image"); }).find("NUL"),
        std::string::npos);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

TEST(Threads, CountsBeyondTheLimitAreRefusedAndBeyondTheCoresRunAsTheCores) {
    EXPECT_NO_THROW(check_threads(0));
    EXPECT_NO_THROW(check_threads(kMaxThreads));
    EXPECT_THROW(check_threads(kMaxThreads + 1), ConfigError);
    EXPECT_THROW(check_threads(-1), ConfigError);
    EXPECT_THROW(in_arena(1000000, [] {}), ConfigError);
    int seen = 0;
    in_arena(kMaxThreads, [&] { seen = tbb::this_task_arena::max_concurrency(); });
    EXPECT_EQ(seen, tbb::info::default_concurrency());
}

}  // namespace deepsea
