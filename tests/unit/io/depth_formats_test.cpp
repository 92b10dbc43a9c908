// PFM and .npy depth, read through read_depth as users do: row and byte order, dtypes, shapes.

#include "deepsea/io/depth_formats.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "io_fixtures.h"

namespace deepsea {
namespace {

using test::be32;
using test::raw;
using test::write_bytes;

class DepthFormats : public test::TempFolderTest {};

std::string npy(const std::string& descr, const std::string& shape, const std::string& data) {
    std::string header =
        "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
    while ((10 + header.size() + 1) % 64 != 0) header += ' ';
    header += '\n';
    const auto n = std::uint16_t(header.size());
    return std::string("\x93NUMPY\x01\x00", 8) + char(n & 0xff) + char(n >> 8) + header + data;
}

TEST_F(DepthFormats, PfmRowsEndUpTopToBottom) {
    // 2 x 2, bottom row (3, 4) stored first, little-endian (negative scale).
    write_bytes(path("d.pfm"), "Pf\n2 2\n-1.0\n" + raw(std::vector<float>{3, 4, 1, 2}));
    Image d = read_depth(path("d.pfm"));
    EXPECT_EQ(d.data, (std::vector<float>{1, 2, 3, 4}));
    // Big-endian (positive scale) gives the same image.
    std::string be;
    for (float v : {3.0f, 4.0f, 1.0f, 2.0f}) {
        std::uint32_t u;
        std::memcpy(&u, &v, 4);
        be += be32(u);
    }
    write_bytes(path("be.pfm"), "Pf\n2 2\n1.0\n" + be);
    EXPECT_EQ(read_depth(path("be.pfm")).data, (std::vector<float>{1, 2, 3, 4}));
}

TEST_F(DepthFormats, NpyDepth) {
    write_bytes(path("f4.npy"), npy("<f4", "(2, 3)", raw(std::vector<float>{1, 2, 3, 4, 5, 6})));
    Image d = read_depth(path("f4.npy"));
    ASSERT_EQ(d.width, 3);
    ASSERT_EQ(d.height, 2);
    EXPECT_EQ(d.at(2, 0), 3.0f);
    EXPECT_EQ(d.at(0, 1), 4.0f);

    write_bytes(path("f8.npy"), npy("<f8", "(2, 2, 1)", raw(std::vector<double>{1.5, 2, 3, 4})));
    EXPECT_EQ(read_depth(path("f8.npy")).data, (std::vector<float>{1.5, 2, 3, 4}));

    write_bytes(path("u2.npy"), npy("<u2", "(1, 2)", raw(std::vector<std::uint16_t>{1500, 0})));
    EXPECT_NEAR(read_depth(path("u2.npy")).at(0, 0), 1.5, 1e-6);

    write_bytes(path("bad.npy"), npy("<f4", "(1, 1, 3)", raw(std::vector<float>{1, 2, 3})));
    EXPECT_THROW(read_depth(path("bad.npy")), InputError);
    write_bytes(path("short.npy"), npy("<f4", "(4, 4)", raw(std::vector<float>{1, 2})));
    EXPECT_THROW(read_depth(path("short.npy")), IoError);
}

TEST_F(DepthFormats, PfmColourAndDirectReaders) {
    // "PF": three channels, read as they are by read_pfm and as colour by read_color.
    write_bytes(path("c.pfm"), "PF\n1 1\n-1.0\n" + raw(std::vector<float>{0.25f, 2.0f, 0.5f}));
    const Image c = read_pfm(path("c.pfm"));
    ASSERT_EQ(c.channels, 3);
    EXPECT_EQ(c.data, (std::vector<float>{0.25f, 2.0f, 0.5f}));
    EXPECT_EQ(read_color(path("c.pfm")).data, c.data);
    EXPECT_THROW(read_depth(path("c.pfm")), InputError);  // three channels, none chosen
    DepthReadOptions g;
    g.channel = "G";
    EXPECT_EQ(read_depth(path("c.pfm"), g).data, (std::vector<float>{2.0f}));
    write_bytes(path("u2.npy"), npy("<u2", "(1, 1)", raw(std::vector<std::uint16_t>{250})));
    EXPECT_NEAR(read_npy(path("u2.npy"), 0.01).at(0, 0), 2.5, 1e-6);
    write_bytes(path("bad.pfm"), "P6\n1 1\n255\n");
    EXPECT_THROW(read_pfm(path("bad.pfm")), IoError);
}

// A header claiming more data than the file holds is refused before the data is allocated
// (found by fuzz_depth: a 40-byte file claiming 10000x10000 doubles cost 800 MB first).
TEST_F(DepthFormats, HeaderClaimingMoreThanTheFileHoldsIsRefusedFirst) {
    write_bytes(path("big.npy"), npy("<f8", "(10000, 10000)", raw(std::vector<double>{1, 2})));
    try {
        read_depth(path("big.npy"));
        FAIL() << "no error";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("800000000 bytes"), std::string::npos) << e.what();
    }
    write_bytes(path("big.pfm"), "PF\n9000 9000\n-1.0\n" + raw(std::vector<float>{1, 2, 3}));
    EXPECT_THROW(read_pfm(path("big.pfm")), IoError);
}

// OpenEXR allocates a header attribute at its stated size before reading it (found by
// fuzz_depth: a 273-byte EXR whose attribute claimed 2.4 GB took 11 s); deepsea walks the
// header first.
TEST_F(DepthFormats, ExrAttributeLargerThanTheFileIsRefusedBeforeOpenExr) {
    const std::string attr =
        std::string("capDate\0string\0", 15) + std::string("\x00\x00\x00\x70", 4);
    write_bytes(path("big.exr"),
                std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) + attr + "2026");
    try {
        read_depth(path("big.exr"));
        FAIL() << "no error";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("attribute 'capDate' claims"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW(read_color(path("big.exr")), IoError);
    // A real EXR passes the walk.
    Image d(3, 2, 1, 1.5f);
    write_depth_exr(path("ok.exr"), d);
    EXPECT_EQ(read_depth(path("ok.exr")).at(2, 1), 1.5f);
}

}  // namespace
}  // namespace deepsea
