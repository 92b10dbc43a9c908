#include "deepsea/io/image_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "deepsea/colour/srgb.h"
#include "deepsea/core/error.h"
#include "io_fixtures.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;
using test::be32;
using test::raw;
using test::write_bytes;

class ImageIo : public test::TempFolderTest {};

Image ramp(int w, int h, int c) {
    Image img(w, h, c);
    for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i % 97) / 96.0f;
    return img;
}

// --- PNG writer for a 16-bit grey image: uncompressed deflate blocks, so no zlib needed -------

std::uint32_t crc32(const std::string& s) {
    std::uint32_t c = 0xffffffffu;
    for (unsigned char b : s) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

std::string chunk(const std::string& type, const std::string& data) {
    return be32(std::uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

std::string png16_grey(int w, int h, const std::vector<std::uint16_t>& px) {
    std::string rows;
    for (int y = 0; y < h; ++y) {
        rows += '\0';  // filter: none
        for (int x = 0; x < w; ++x) {
            const std::uint16_t v = px[std::size_t(y) * w + x];
            rows += char(v >> 8);
            rows += char(v & 0xff);
        }
    }
    std::uint32_t a = 1, b = 0;
    for (unsigned char ch : rows) a = (a + ch) % 65521, b = (b + a) % 65521;
    std::string z = "\x78\x01";
    const auto len = std::uint16_t(rows.size());
    z += '\x01';  // final stored block
    z += char(len & 0xff);
    z += char(len >> 8);
    z += char(~len & 0xff);
    z += char((~len >> 8) & 0xff);
    z += rows + be32((b << 16) | a);
    std::string ihdr = be32(std::uint32_t(w)) + be32(std::uint32_t(h));
    // 16 bits, grey, deflate, no filter, no interlace
    ihdr += std::string("\x10\x00\x00\x00\x00", 5);
    return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", z) +
           chunk("IEND", "");
}

// --- colour ----------------------------------------------------------------------------------

TEST_F(ImageIo, Png8RoundTripWithinQuantisation) {
    const Image img = ramp(17, 9, 3);
    write_color(path("a.png"), img, 8);
    const Image back = read_color(path("a.png"));
    ASSERT_EQ(back.width, 17);
    ASSERT_EQ(back.height, 9);
    ASSERT_EQ(back.channels, 3);
    for (std::size_t i = 0; i < img.data.size(); ++i)
        EXPECT_NEAR(linear_to_srgb(back.data[i]), linear_to_srgb(img.data[i]), 0.5 / 255 + 1e-5);
    EXPECT_EQ(listing(), std::vector<std::string>{"a.png"});
}

TEST_F(ImageIo, Png16RoundTripWithinQuantisation) {
    const Image img = ramp(11, 7, 3);
    write_color(path("a.png"), img, 16);
    const Image back = read_color(path("a.png"));
    for (std::size_t i = 0; i < img.data.size(); ++i)
        EXPECT_NEAR(linear_to_srgb(back.data[i]), linear_to_srgb(img.data[i]), 0.5 / 65535 + 2e-6);
}

TEST_F(ImageIo, ColourIsClampedAndGreyExpanded) {
    Image grey(3, 2, 1, 0.25f);
    grey.at(0, 0) = 7.0f;
    grey.at(1, 0) = -1.0f;
    write_color(path("g.png"), grey, 8);
    const Image back = read_color(path("g.png"));
    ASSERT_EQ(back.channels, 3);
    EXPECT_FLOAT_EQ(back.at(0, 0, 2), 1.0f);
    EXPECT_FLOAT_EQ(back.at(1, 0, 0), 0.0f);
    EXPECT_NEAR(back.at(2, 1, 1), 0.25, 0.004);
}

TEST_F(ImageIo, JpegAndTiffWrite) {
    const Image img = ramp(16, 16, 3);
    write_color(path("a.jpg"), img, 16);  // JPEG is always 8-bit
    write_color(path("a.tif"), img, 16);
    EXPECT_EQ(read_color(path("a.jpg")).width, 16);
    const Image t = read_color(path("a.tif"));
    for (std::size_t i = 0; i < img.data.size(); ++i)
        EXPECT_NEAR(linear_to_srgb(t.data[i]), linear_to_srgb(img.data[i]), 0.5 / 65535 + 2e-6);
}

TEST_F(ImageIo, ExrColourKeepsLinearValuesAboveOne) {
    Image img = ramp(5, 4, 3);
    img.at(0, 0, 0) = 12.5f;
    write_color(path("a.exr"), img);
    const Image back = read_color(path("a.exr"));
    for (std::size_t i = 0; i < img.data.size(); ++i)
        EXPECT_NEAR(back.data[i], img.data[i], 1e-3 * std::max(1.0f, img.data[i]));
}

TEST_F(ImageIo, ExrLayersRoundTripExactly) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-5.0f, 50.0f);
    Image rgb(6, 5, 3), depth(6, 5, 1);
    for (auto& v : rgb.data) v = u(rng);
    for (auto& v : depth.data) v = u(rng);
    depth.data[3] = std::numeric_limits<float>::infinity();
    write_exr_layers(path("l.exr"), {{"final", &rgb, {"R", "G", "B"}}, {"depth", &depth, {"Z"}}});
    EXPECT_EQ(read_exr_layer(path("l.exr"), "final", {"R", "G", "B"}).data, rgb.data);
    EXPECT_EQ(read_exr_layer(path("l.exr"), "depth", {"Z"}).data, depth.data);
    EXPECT_THROW(read_exr_layer(path("l.exr"), "normal", {"X"}), InputError);
    // The multi-layer file has exactly one depth-like channel: read_depth picks depth.Z.
    EXPECT_EQ(read_depth(path("l.exr")).data, depth.data);
}

TEST_F(ImageIo, ExrLayersOfDifferentSizesAreAnInputError) {
    Image a(4, 4, 3), b(4, 5, 1);
    EXPECT_THROW(
        write_exr_layers(path("l.exr"), {{"final", &a, {"R", "G", "B"}}, {"depth", &b, {"Z"}}}),
        InputError);
    EXPECT_TRUE(listing().empty());
}

// --- depth -----------------------------------------------------------------------------------

TEST_F(ImageIo, DepthExrWithAnySingleChannelName) {
    Image d(4, 3, 1);
    for (std::size_t i = 0; i < d.data.size(); ++i) d.data[i] = 0.5f + float(i);
    for (const std::string name : {"Y", "Z", "R", "depth"}) {
        const std::string p = path("d_" + name + ".exr");
        write_exr_layers(p, {{"", &d, {name}}});
        EXPECT_EQ(read_depth(p).data, d.data) << name;
    }
    write_depth_exr(path("z.exr"), d);
    EXPECT_EQ(read_depth(path("z.exr")).data, d.data);
    EXPECT_EQ(read_exr_layer(path("z.exr"), "", {"Z"}).data, d.data);
}

TEST_F(ImageIo, SeveralDepthChannelsNeedAChoice) {
    Image rgb(3, 2, 3);
    for (std::size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = float(i);
    write_exr_layers(path("rgb.exr"), {{"", &rgb, {"R", "G", "B"}}});
    try {
        read_depth(path("rgb.exr"));
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("rgb.exr has channels R, G, B: name the depth channel to use"),
                  std::string::npos)
            << msg;
    }
    DepthReadOptions opt;
    opt.channel = "G";
    const Image g = read_depth(path("rgb.exr"), opt);
    ASSERT_EQ(g.channels, 1);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(g.data[i], rgb.data[i * 3 + 1]);
    opt.channel = "Q";
    try {
        read_depth(path("rgb.exr"), opt);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("R, G, B"), std::string::npos) << e.what();
    }
}

TEST_F(ImageIo, OneZChannelAmongSeveralIsPicked) {
    Image img(2, 2, 3);
    for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i);
    write_exr_layers(path("rgz.exr"), {{"", &img, {"R", "G", "Z"}}});
    const Image d = read_depth(path("rgz.exr"));
    for (int i = 0; i < 4; ++i) EXPECT_EQ(d.data[i], img.data[i * 3 + 2]);
}

TEST_F(ImageIo, Png16DepthIsScaled) {
    const std::vector<std::uint16_t> px = {0, 1, 1000, 2500, 65535, 40000};
    write_bytes(path("d.png"), png16_grey(3, 2, px));
    const Image d = read_depth(path("d.png"));  // default 0.001 m per unit
    ASSERT_EQ(d.width, 3);
    ASSERT_EQ(d.height, 2);
    for (std::size_t i = 0; i < px.size(); ++i)
        EXPECT_NEAR(d.data[i], px[i] * 0.001, 1e-6 + 1e-7 * px[i]);  // float precision
    DepthReadOptions opt;
    opt.scale = 0.0001;
    EXPECT_NEAR(read_depth(path("d.png"), opt).at(0, 1), 0.25, 1e-6);
}

TEST_F(ImageIo, EightBitDepthIsAnInputError) {
    write_color(path("d8.png"), Image(4, 4, 1, 0.5f), 8);
    EXPECT_THROW(read_depth(path("d8.png")), InputError);
}

// --- errors ----------------------------------------------------------------------------------

TEST_F(ImageIo, MissingOrCorruptFileIsAnIoErrorOnOneLine) {
    for (const std::string name : {"none.png", "none.exr", "none.npy", "none.pfm"}) {
        try {
            read_depth(path(name));
            FAIL() << name;
        } catch (const IoError& e) {
            EXPECT_EQ(std::string(e.what()).rfind(path(name) + ": ", 0), 0u) << e.what();
        }
    }
    EXPECT_THROW(read_color(path("none.png")), IoError);
    write_bytes(path("junk.png"), "this is not a png\nat all\n");
    write_bytes(path("junk.exr"), std::string("\x76\x2f\x31\x01garbage", 11));
    for (const std::string name : {"junk.png", "junk.exr"}) {
        try {
            read_color(path(name));
            FAIL() << name;
        } catch (const IoError& e) {
            const std::string msg = e.what();
            EXPECT_EQ(msg.rfind(path(name) + ": ", 0), 0u) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }
}

TEST_F(ImageIo, WritingIntoAMissingFolderIsAnIoError) {
    const std::string p = path("no/such/folder/out.png");
    try {
        write_color(p, ramp(2, 2, 3));
        FAIL();
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(listing().empty());
}

TEST_F(ImageIo, WritingIntoAReadOnlyFolderIsAnIoErrorAndLeavesNothing) {
    fs::create_directories(dir_ / "ro");
    fs::permissions(dir_ / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    if (::access((dir_ / "ro").c_str(), W_OK) == 0) GTEST_SKIP() << "running as root";
    const Image img = ramp(3, 3, 3);
    EXPECT_THROW(write_color(path("ro/out.png"), img), IoError);
    EXPECT_THROW(write_depth_exr(path("ro/d.exr"), Image(3, 3, 1)), IoError);
    fs::permissions(dir_ / "ro", fs::perms::owner_all);
    EXPECT_TRUE(fs::is_empty(dir_ / "ro"));
}

TEST_F(ImageIo, FailedRenameRemovesTheTemporary) {
    // The target is a non-empty folder: the image is written, the rename fails.
    fs::create_directories(dir_ / "out.png" / "x");
    EXPECT_THROW(write_color(path("out.png"), ramp(3, 3, 3)), IoError);
    EXPECT_EQ(listing(), std::vector<std::string>{"out.png"});
}

TEST_F(ImageIo, OverwriteReplacesAtomically) {
    write_color(path("a.png"), Image(2, 2, 3, 0.0f));
    write_color(path("a.png"), Image(2, 2, 3, 1.0f));
    EXPECT_FLOAT_EQ(read_color(path("a.png")).at(1, 1, 2), 1.0f);
    EXPECT_EQ(listing(), std::vector<std::string>{"a.png"});
}

// Deflate packs at most 1032 bytes into one: a 60-byte PNG cannot hold 9000x9000 pixels, and is
// refused before OIIO allocates the image (found by fuzz_image: it cost 0.3 s and a gigabyte).
TEST_F(ImageIo, PngClaimingMoreThanItCanHoldIsRefusedBeforeAllocating) {
    std::string ihdr = be32(9000) + be32(9000) + std::string("\x08\x00\x00\x00\x00", 5);
    const std::string tiny = png16_grey(1, 1, {7});
    const std::string idat = tiny.substr(8 + 25);  // the 1x1 file's IDAT and IEND
    write_bytes(path("claims.png"),
                std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + idat);
    for (auto read : {+[](const std::string& p) { (void)read_color(p); },
                      +[](const std::string& p) { (void)read_depth(p); }}) {
        try {
            read(path("claims.png"));
            FAIL() << "no error";
        } catch (const IoError& e) {
            EXPECT_NE(std::string(e.what()).find("claims 9000x9000 pixels"), std::string::npos)
                << e.what();
        }
    }
    // A large image that deflates well is still read.
    write_bytes(path("flat.png"), png16_grey(64, 64, std::vector<std::uint16_t>(64 * 64, 9)));
    EXPECT_EQ(read_depth(path("flat.png")).width, 64);
}

}  // namespace
}  // namespace deepsea
