// The PNG reader's own inflate (ISA-L) against the streams other encoders make: every kind of
// deflate block (stored, fixed and dynamic codes, runs, long matches), each decoded to the
// samples that were compressed and to OpenImageIO's (libpng's); a damaged Adler-32 refused.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <isa-l.h>
#include <libdeflate.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "io_fixtures.h"

namespace deepsea {
namespace {

class PngInflate : public test::TempFolderTest {};

/// A w x h 8-bit RGB PNG: the rows unfiltered (filter byte 0), `stream` their zlib stream.
std::string png_of(int w, int h, const std::vector<std::uint8_t>& stream) {
    std::string png("\x89PNG\r\n\x1a\n", 8);
    const auto chunk = [&](const char* type, const std::string& data) {
        std::string c = test::be32(std::uint32_t(data.size())) + std::string(type, 4) + data;
        png += c + test::be32(libdeflate_crc32(0, c.data() + 4, c.size() - 4));
    };
    chunk("IHDR", test::be32(std::uint32_t(w)) + test::be32(std::uint32_t(h)) +
                      std::string("\x08\x02\x00\x00\x00", 5));
    chunk("IDAT", std::string(stream.begin(), stream.end()));
    chunk("IEND", "");
    return png;
}

/// Rows with a filter byte each: smooth ramps, flat runs, repeated stretches and noise, so
/// that encoders emit literals, runs and long matches.
std::vector<std::uint8_t> rows_of(int w, int h, std::vector<std::uint8_t>& samples) {
    std::mt19937 rng(11);
    std::vector<std::uint8_t> rows;
    for (int y = 0; y < h; ++y) {
        rows.push_back(0);
        for (int i = 0; i < 3 * w; ++i) {
            const int band = (y / 8) % 4;
            const std::uint8_t v = band == 0   ? std::uint8_t(i + y)
                                   : band == 1 ? std::uint8_t(40)
                                   : band == 2 ? std::uint8_t((i % 17) * 9)
                                               : std::uint8_t(rng());
            rows.push_back(v);
            samples.push_back(v);
        }
    }
    return rows;
}

std::vector<std::uint8_t> libdeflate_stream(const std::vector<std::uint8_t>& rows, int level) {
    libdeflate_compressor* z = libdeflate_alloc_compressor(level);
    std::vector<std::uint8_t> out(libdeflate_zlib_compress_bound(z, rows.size()));
    out.resize(libdeflate_zlib_compress(z, rows.data(), rows.size(), out.data(), out.size()));
    libdeflate_free_compressor(z);
    return out;
}

std::vector<std::uint8_t> isal_stream(const std::vector<std::uint8_t>& rows, int level) {
    std::vector<std::uint8_t> out(rows.size() * 2 + 1024);
    std::vector<std::uint8_t> buf(level == 0 ? 0 : ISAL_DEF_LVL3_DEFAULT);
    isal_zstream s;
    isal_deflate_init(&s);
    s.gzip_flag = IGZIP_ZLIB;
    s.level = std::uint32_t(level);
    s.level_buf = buf.empty() ? nullptr : buf.data();
    s.level_buf_size = std::uint32_t(buf.size());
    s.end_of_stream = 1;
    s.flush = NO_FLUSH;
    s.next_in = const_cast<std::uint8_t*>(rows.data());
    s.avail_in = std::uint32_t(rows.size());
    s.next_out = out.data();
    s.avail_out = std::uint32_t(out.size());
    EXPECT_EQ(isal_deflate(&s), COMP_OK);
    EXPECT_EQ(s.internal_state.state, ZSTATE_END);
    out.resize(s.total_out);
    return out;
}

std::vector<std::uint8_t> oiio_codes(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    std::vector<std::uint8_t> px(std::size_t(in->spec().width) * in->spec().height * 3);
    EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
    return px;
}

TEST_F(PngInflate, StreamsOfEveryEncoderDecodeToTheirSamples) {
    const int w = 301, h = 97;  // 90 kB of rows: more than one deflate block, matches far back
    std::vector<std::uint8_t> samples;
    const std::vector<std::uint8_t> rows = rows_of(w, h, samples);
    std::vector<std::pair<std::string, std::vector<std::uint8_t>>> streams;
    for (const int level : {0, 1, 6, 12})  // 0: stored blocks
        streams.emplace_back("libdeflate" + std::to_string(level), libdeflate_stream(rows, level));
    for (const int level : {0, 1, 3})  // 0: ISA-L's static code
        streams.emplace_back("isal" + std::to_string(level), isal_stream(rows, level));
    Frame frame;
    for (const auto& [name, stream] : streams) {
        const std::string p = path(name + ".png");
        test::write_bytes(p, png_of(w, h, stream));
        read_frame_color(p, frame);
        ASSERT_EQ(frame.codes.bits, 8) << name;
        EXPECT_EQ(frame.codes.rgb8, samples) << name;
        EXPECT_EQ(frame.codes.rgb8, oiio_codes(p)) << name;
    }
}

TEST_F(PngInflate, ADamagedChecksumOrAShortStreamIsAnErrorNamingTheFile) {
    const int w = 64, h = 40;
    std::vector<std::uint8_t> samples;
    const std::vector<std::uint8_t> stream = libdeflate_stream(rows_of(w, h, samples), 6);
    std::vector<std::uint8_t> adler = stream;
    adler.back() ^= 1;  // the chunk's CRC is of the damaged bytes: only Adler-32 tells
    std::vector<std::uint8_t> rows_short = libdeflate_stream(rows_of(w, h - 1, samples), 6);
    for (const auto& [name, s] :
         {std::pair{std::string("adler"), adler}, std::pair{std::string("short"), rows_short}}) {
        const std::string p = path(name + ".png");
        test::write_bytes(p, png_of(w, h, s));
        const std::string msg = test::error_of([&] { (void)read_color(p); });
        EXPECT_EQ(msg.rfind(p + ": ", 0), 0u) << name << ": " << msg;
    }
}

}  // namespace
}  // namespace deepsea
