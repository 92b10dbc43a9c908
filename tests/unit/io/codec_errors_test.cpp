// The codecs' guards: damaged and oversized files are one-line errors naming the file, and a
// failed write leaves nothing behind.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "io_fixtures.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::probe_image;

class CodecErrors : public test::TempFolderTest {};

TEST_F(CodecErrors, CorruptOrTruncatedFilesAreOneLineIoErrorsNamingTheFile) {
    write_color(path("ok.png"), probe_image(64, 48), 8);
    write_color(path("ok16.png"), Image(64, 48, 1, 0.5f), 16);
    write_color(path("ok.jpg"), probe_image(64, 48), 8);
    Image depth(64, 48, 1, 3.0f);
    write_depth_exr(path("ok.exr"), depth);
    for (const std::string f : {"ok.png", "ok16.png", "ok.jpg", "ok.exr"}) {
        std::ifstream is(path(f), std::ios::binary);
        const std::string bytes{std::istreambuf_iterator<char>(is), {}};
        const std::string ext = fs::path(f).extension().string();
        std::vector<std::pair<std::string, std::string>> damaged;
        for (std::size_t cut :
             {std::size_t(8), std::size_t(40), bytes.size() / 2, bytes.size() - 5}) {
            damaged.emplace_back("cut" + std::to_string(cut) + ext, bytes.substr(0, cut));
        }
        std::string flipped = bytes;
        for (std::size_t i = bytes.size() / 3; i < bytes.size() / 3 + 64; ++i) flipped[i] ^= 0x5a;
        damaged.emplace_back("flip" + ext, flipped);
        for (const auto& [name, content] : damaged) {
            const std::string p = path(f.substr(0, f.size() - ext.size()) + "-" + name);
            test::write_bytes(p, content);
            const std::string msg = error_of([&] {
                if (ext == ".exr") {
                    (void)read_depth(p);
                    (void)read_exr_layer(p, "", {"Z"});
                } else if (f == "ok16.png") {
                    (void)read_depth(p);
                } else {
                    (void)read_color(p);
                }
            });
            // Damaged entropy data may still decode to some pixels (nothing says it is wrong),
            // and a PNG whose last 5 bytes (of its end chunk) are cut still has all its pixels.
            if (msg.empty() && ext == ".jpg" && name.rfind("flip", 0) == 0) continue;
            if (msg.empty() && ext == ".png" && content.size() + 5 == bytes.size()) continue;
            EXPECT_EQ(msg.rfind(p + ": ", 0), 0u) << p << ": " << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }
}

TEST_F(CodecErrors, DamagedPngAndJpegNameTheFileAndNoCodecPrintsOnStderr) {
    // Each codec's error comes back through its own hook (libjpeg's error manager, libspng's
    // return codes, OpenImageIO's geterror()), and nothing reaches stderr: libpng, inside
    // OpenImageIO, printed its errors there before deepsea's one line, so no PNG goes to
    // OpenImageIO, not even under another name (.tif here, whose reader would pass it on).
    // As depth (channel R), the 8-bit files are refused after their header is read.
    write_color(path("ok.png"), probe_image(64, 48), 8);
    write_color(path("ok16.png"), probe_image(64, 48), 16);
    write_color(path("ok.jpg"), probe_image(64, 48), 8);
    for (const std::string f : {"ok.png", "ok16.png", "ok.jpg"}) {
        std::ifstream is(path(f), std::ios::binary);
        const std::string bytes{std::istreambuf_iterator<char>(is), {}};
        const std::string ext = fs::path(f).extension().string();
        std::vector<std::pair<std::string, std::string>> damaged;
        for (std::size_t cut : {std::size_t(8), std::size_t(30), std::size_t(60), std::size_t(200),
                                bytes.size() / 2, bytes.size() - 5}) {
            damaged.emplace_back("cut" + std::to_string(cut), bytes.substr(0, cut));
        }
        std::string flipped = bytes;
        for (std::size_t i = bytes.size() / 3; i < bytes.size() / 3 + 64; ++i) flipped[i] ^= 0x5a;
        damaged.emplace_back("flip", flipped);
        for (const auto& [name, content] : damaged) {
            for (const std::string& as : {ext, std::string(".tif")}) {
                const std::string p = path(f.substr(0, f.size() - ext.size()) + "-" + name + as);
                test::write_bytes(p, content);
                for (const bool depth : {false, true}) {
                    testing::internal::CaptureStderr();
                    const std::string msg = error_of([&] {
                        if (depth) {
                            DepthReadOptions opt;
                            opt.channel = "R";
                            (void)read_depth(p, opt);
                        } else {
                            (void)read_color(p);
                        }
                    });
                    const std::string printed = testing::internal::GetCapturedStderr();
                    EXPECT_EQ(printed, "") << p << (depth ? " as depth" : " as colour");
                    // As in CorruptOrTruncatedFilesAreOneLineIoErrorsNamingTheFile: damaged
                    // entropy data may still decode, a PNG cut in its end chunk has its pixels.
                    if (msg.empty() && ext == ".jpg" && name == "flip") continue;
                    if (msg.empty() && ext == ".png" && content.size() + 5 == bytes.size())
                        continue;
                    // OpenImageIO's JPEG reader (a JPEG under another name) fills the rows a
                    // cut file lacks, as libjpeg does, where deepsea's own reader refuses it.
                    if (msg.empty() && ext == ".jpg" && as == ".tif" && !depth) continue;
                    EXPECT_EQ(msg.rfind(p, 0), 0u) << p << (depth ? " as depth: " : ": ") << msg;
                    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
                }
            }
        }
    }
}

TEST_F(CodecErrors, HeaderSizesBeyondTheLimitAreRefusedBeforeAllocating) {
    // A valid 2x2 PNG and EXR whose headers are edited to claim 20000 x 20000.
    write_color(path("small.png"), Image(2, 2, 3, 0.5f), 8);
    write_depth_exr(path("small.exr"), Image(2, 2, 1, 1.0f));
    {
        std::fstream f(path("small.png"), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(16);
        f.write(test::be32(20000).data(), 4);
        f.write(test::be32(20000).data(), 4);
    }
    EXPECT_NE(error_of([&] { (void)read_color(path("small.png")); }).find("small.png"),
              std::string::npos);
    std::ifstream is(path("small.exr"), std::ios::binary);
    std::string bytes{std::istreambuf_iterator<char>(is), {}};
    is.close();
    const std::string key = std::string("dataWindow\0box2i\0", 17);
    const std::size_t at = bytes.find(key);
    ASSERT_NE(at, std::string::npos);
    const std::int32_t big = 19999;
    std::memcpy(&bytes[at + key.size() + 4 + 8], &big, 4);   // max.x
    std::memcpy(&bytes[at + key.size() + 4 + 12], &big, 4);  // max.y
    test::write_bytes(path("big.exr"), bytes);
    const std::string msg = error_of([&] { (void)read_depth(path("big.exr")); });
    EXPECT_EQ(msg.rfind(path("big.exr") + ":", 0), 0u) << msg;
}

TEST_F(CodecErrors, PngWriteFailureLeavesNothing) {
    fs::create_directories(dir_ / "out.png" / "x");  // the rename onto a full folder fails
    EXPECT_THROW(write_color(path("out.png"), Image(3, 3, 3, 0.2f)), IoError);
    EXPECT_THROW(write_color(path("out.jpg/"), Image(3, 3, 3, 0.2f)), IoError);
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir_)) left.push_back(e.path().filename());
    EXPECT_EQ(left, std::vector<std::string>{"out.png"});
}

}  // namespace
}  // namespace deepsea
