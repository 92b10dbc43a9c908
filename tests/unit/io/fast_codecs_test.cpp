// The fast PNG/JPEG/EXR paths of image_io against OpenImageIO: the same integer codes, and
// files that OpenImageIO decodes with their metadata (their guards: codec_errors_test.cpp).

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <libdeflate.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "deepsea/colour/srgb.h"
#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "io_fixtures.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

class FastCodecs : public test::TempFolderTest {};

using test::probe_image;

/// The file's pixels as OpenImageIO decodes them, as `type` (alpha unassociated, as deepsea
/// reads it).
template <class T>
std::vector<T> oiio_pixels(const std::string& path, OIIO::TypeDesc type, int* channels = nullptr) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    const auto& spec = in->spec();
    if (channels) *channels = spec.nchannels;
    std::vector<T> px(std::size_t(spec.width) * spec.height * spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, type, px.data()));
    return px;
}

/// Compares two code lists: every code within 1, and at most `max_off` of them off by one.
template <class T>
void expect_codes_match(const std::vector<T>& a, const std::vector<T>& b, std::size_t max_off) {
    ASSERT_EQ(a.size(), b.size());
    std::size_t off = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_LE(std::abs(int(a[i]) - int(b[i])), 1) << i;
        off += a[i] != b[i];
    }
    EXPECT_LE(off, max_off);
}

TEST_F(FastCodecs, PngCodesAreOpenImageIOs) {
    // TIFF still goes through OpenImageIO's float to integer conversion: the reference. It is
    // the same except where value x codes lies within an ulp of k + 1/2: OpenImageIO's own
    // vector and scalar loops disagree there (its output depends on the pixel's position), and
    // the probe puts about 2 % of its values there on purpose; a rendered frame has none
    // (docs/runtime.md).
    const Image img = probe_image(256, 128);
    const std::size_t n = img.data.size();
    for (int bits : {8, 16}) {
        write_color(path("a.png"), img, bits);
        write_color(path("a.tif"), img, bits);
        if (bits == 8) {
            expect_codes_match(oiio_pixels<std::uint8_t>(path("a.png"), OIIO::TypeDesc::UINT8),
                               oiio_pixels<std::uint8_t>(path("a.tif"), OIIO::TypeDesc::UINT8),
                               n / 1000);
        } else {
            expect_codes_match(oiio_pixels<std::uint16_t>(path("a.png"), OIIO::TypeDesc::UINT16),
                               oiio_pixels<std::uint16_t>(path("a.tif"), OIIO::TypeDesc::UINT16),
                               n / 1000);
        }
    }
    // Random values (no engineered ties) come out identical.
    Image rnd(128, 128, 3);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (float& v : rnd.data) v = u(rng) * u(rng);
    write_color(path("r.png"), rnd, 8);
    write_color(path("r.tif"), rnd, 8);
    EXPECT_EQ(oiio_pixels<std::uint8_t>(path("r.png"), OIIO::TypeDesc::UINT8),
              oiio_pixels<std::uint8_t>(path("r.tif"), OIIO::TypeDesc::UINT8));
}

/// What read_color makes of a value OpenImageIO decoded as float from a `codes`-level file.
float decoded(float f, int codes) {
    return srgb_to_linear(float(std::lround(f * codes)) / float(codes));
}

TEST_F(FastCodecs, ExposureWhileEncodingEqualsAnExposedCopy) {
    const Image img = probe_image(64, 64);
    Image exposed = img;
    for (float& v : exposed.data) v = float(v * 3.7);
    write_color(path("a.png"), img, 8, {}, 3.7);
    write_color(path("b.png"), exposed, 8);
    EXPECT_EQ(read_color(path("a.png")).data, read_color(path("b.png")).data);
}

TEST_F(FastCodecs, PngDecodesWithOpenImageIOWithItsMetadata) {
    const Image img = probe_image(33, 17);
    const ImageMetadata meta{{"deepsea:exposure", "1.25"}, {"deepsea:asset_hash", "fnv1a64:ab"}};
    for (int bits : {8, 16}) {
        write_color(path("m.png"), img, bits, meta);
        auto in = OIIO::ImageInput::open(path("m.png"));
        ASSERT_TRUE(in) << OIIO::geterror();
        const auto& spec = in->spec();
        EXPECT_EQ(spec.width, 33);
        EXPECT_EQ(spec.nchannels, 3);
        EXPECT_EQ(spec.format, bits == 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16);
        EXPECT_EQ(spec.get_string_attribute("deepsea:exposure"), "1.25");
        EXPECT_EQ(spec.get_string_attribute("deepsea:asset_hash"), "fnv1a64:ab");
        EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
        // read_color (libspng) decodes what OpenImageIO decodes.
        const std::vector<float> f = oiio_pixels<float>(path("m.png"), OIIO::TypeDesc::FLOAT);
        const Image back = read_color(path("m.png"));
        ASSERT_EQ(back.data.size(), f.size());
        for (std::size_t i = 0; i < f.size(); ++i)
            ASSERT_EQ(back.data[i], decoded(f[i], bits == 8 ? 255 : 65535)) << i;
    }
    write_color(path("grey.png"), Image(5, 4, 1, 0.5f), 8);
    int channels = 0;
    (void)oiio_pixels<std::uint8_t>(path("grey.png"), OIIO::TypeDesc::UINT8, &channels);
    EXPECT_EQ(channels, 1);
    EXPECT_EQ(read_color(path("grey.png")).channels, 3);
}

/// A 19x7 PNG of `nch` channels (grey, grey + alpha, RGB, RGBA) and `type` (8 or 16 bits) of
/// random values, written by OpenImageIO itself (libpng), the values as they are (alpha
/// unassociated). False if OpenImageIO fails.
bool write_oiio_png(const std::string& p, int nch, OIIO::TypeDesc type, std::mt19937& rng) {
    OIIO::ImageSpec spec(19, 7, nch, type);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    std::vector<std::uint16_t> px(std::size_t(19) * 7 * nch);
    for (auto& v : px) v = std::uint16_t(rng());
    auto out = OIIO::ImageOutput::create(p);
    if (!out || !out->open(p, spec) || !out->write_image(OIIO::TypeDesc::UINT16, px.data()))
        return false;
    return out->close();
}

TEST_F(FastCodecs, PngsOfEveryKindReadAsOpenImageIOReadsThem) {
    // Written by OpenImageIO itself (libpng): grey, grey + alpha, RGB, RGBA at 8 and 16 bits.
    std::mt19937 rng(3);
    for (int nch : {1, 2, 3, 4}) {
        for (OIIO::TypeDesc type : {OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT16}) {
            const std::string p = path("k" + std::to_string(nch) + type.c_str() + ".png");
            ASSERT_TRUE(write_oiio_png(p, nch, type, rng));
            const std::vector<float> f = oiio_pixels<float>(p, OIIO::TypeDesc::FLOAT);
            const Image img = read_color(p);
            ASSERT_EQ(img.channels, 3);
            const int use = nch >= 3 ? 3 : 1;
            for (std::size_t i = 0; i < std::size_t(19) * 7; ++i)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(img.data[i * 3 + c],
                              decoded(f[i * nch + (use == 3 ? c : 0)],
                                      type == OIIO::TypeDesc::UINT8 ? 255 : 65535))
                        << p << " " << i;
        }
    }
}

TEST_F(FastCodecs, PngDepthOfEveryKindReadsAsOpenImageIOReadsIt) {
    // PNG depth is read by libspng (OpenImageIO's libpng prints its errors on stderr): each
    // channel OpenImageIO names (Y, Y A, R G B, R G B A) gives its 16-bit values times the
    // scale; 8-bit files and channels the file lacks are InputErrors naming the channels. Also
    // under another name (.tif), where OpenImageIO would have read it.
    std::mt19937 rng(5);
    for (int nch : {1, 2, 3, 4}) {
        for (OIIO::TypeDesc type : {OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT16}) {
            const std::string p = path("d" + std::to_string(nch) + type.c_str() + ".png");
            ASSERT_TRUE(write_oiio_png(p, nch, type, rng));
            fs::copy_file(p, p + ".tif", fs::copy_options::overwrite_existing);
            auto in = OIIO::ImageInput::open(p);
            ASSERT_TRUE(in);
            const std::vector<std::string> names = in->spec().channelnames;
            in.reset();
            const std::vector<std::uint16_t> ref = oiio_pixels<std::uint16_t>(p, type);
            std::string all;
            for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
            for (const std::string& file : {p, p + ".tif"}) {
                DepthReadOptions opt;
                for (int c = 0; c < nch; ++c) {
                    opt.channel = names[c];
                    if (type == OIIO::TypeDesc::UINT8) {
                        EXPECT_THROW((void)read_depth(file, opt), InputError) << file;
                        continue;
                    }
                    const Image d = read_depth(file, opt);
                    ASSERT_EQ(d.data.size(), std::size_t(19) * 7) << file;
                    for (std::size_t i = 0; i < d.data.size(); ++i)
                        ASSERT_EQ(d.data[i], float(double(ref[i * nch + c]) * 0.001)) << file;
                }
                opt.channel = "Z";
                try {
                    (void)read_depth(file, opt);
                    ADD_FAILURE() << file;
                } catch (const InputError& e) {
                    EXPECT_EQ(e.what(), file + " has no channel 'Z' (it has " + all + ")");
                }
            }
        }
    }
}

TEST_F(FastCodecs, JpegPixelsAreOpenImageIOsAndCarryMetadata) {
    const Image img = probe_image(96, 64);
    write_color(path("fast.jpg"), img, 8, {{"deepsea:exposure", "2.5"}});
    // The same codes through OpenImageIO's own JPEG writer (quality 95, its defaults).
    write_color(path("codes.png"), img, 8);
    const std::vector<std::uint8_t> codes =
        oiio_pixels<std::uint8_t>(path("codes.png"), OIIO::TypeDesc::UINT8);
    {
        auto out = OIIO::ImageOutput::create(path("oiio.jpg"));
        OIIO::ImageSpec spec(96, 64, 3, OIIO::TypeDesc::UINT8);
        spec.attribute("CompressionQuality", 95);
        ASSERT_TRUE(out && out->open(path("oiio.jpg"), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, codes.data()));
        out->close();
    }
    EXPECT_EQ(oiio_pixels<std::uint8_t>(path("fast.jpg"), OIIO::TypeDesc::UINT8),
              oiio_pixels<std::uint8_t>(path("oiio.jpg"), OIIO::TypeDesc::UINT8));
    // read_color (libjpeg-turbo) decodes what OpenImageIO decodes.
    const std::vector<float> f = oiio_pixels<float>(path("fast.jpg"), OIIO::TypeDesc::FLOAT);
    const Image back = read_color(path("fast.jpg"));
    ASSERT_EQ(back.data.size(), f.size());
    for (std::size_t i = 0; i < f.size(); ++i) ASSERT_EQ(back.data[i], decoded(f[i], 255)) << i;
    auto in = OIIO::ImageInput::open(path("fast.jpg"));
    ASSERT_TRUE(in);
    EXPECT_NE(in->spec().get_string_attribute("ImageDescription").find("deepsea:exposure=2.5"),
              std::string::npos);
}

TEST_F(FastCodecs, HalfAndFloatExrLayersRoundTrip) {
    Image rgb(7, 5, 3), depth(7, 5, 1);
    for (std::size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = 0.1f + 1e-3f * float(i);
    for (std::size_t i = 0; i < depth.data.size(); ++i) depth.data[i] = 2.0f + 0.37f * float(i);
    const std::vector<ExrLayer> layers{{"final", &rgb, {"R", "G", "B"}}, {"depth", &depth, {"Z"}}};
    write_exr_layers(path("f.exr"), layers, {{"deepsea:exposure", "3"}});
    write_exr_layers(path("h.exr"), layers, {}, true);
    EXPECT_EQ(read_exr_layer(path("f.exr"), "final", {"R", "G", "B"}).data, rgb.data);
    EXPECT_EQ(read_depth(path("f.exr"), {"depth.Z"}).data, depth.data);
    const Image h = read_exr_layer(path("h.exr"), "final", {"R", "G", "B"});
    for (std::size_t i = 0; i < rgb.data.size(); ++i)
        EXPECT_NEAR(h.data[i], rgb.data[i], rgb.data[i] * 1e-3f);
    for (const char* f : {"f.exr", "h.exr"}) {
        auto in = OIIO::ImageInput::open(path(f));
        ASSERT_TRUE(in) << OIIO::geterror();
        EXPECT_EQ(in->spec().nchannels, 4);
        EXPECT_EQ(in->spec().format, f[0] == 'h' ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    }
    auto in = OIIO::ImageInput::open(path("f.exr"));
    EXPECT_EQ(in->spec().get_string_attribute("deepsea:exposure"), "3");
    EXPECT_GT(fs::file_size(path("f.exr")), fs::file_size(path("h.exr")));
}

TEST_F(FastCodecs, DepthExrReadsTheDataWindowAndHalfChannels) {
    // An EXR whose data window does not start at (0, 0), with a half channel.
    const std::string p = path("win.exr");
    OIIO::ImageSpec spec(6, 4, 1, OIIO::TypeDesc::HALF);
    spec.x = 3;
    spec.y = 2;
    spec.channelnames = {"Z"};
    std::vector<float> z(24);
    for (std::size_t i = 0; i < z.size(); ++i) z[i] = 0.5f * float(i);
    auto out = OIIO::ImageOutput::create(p);
    ASSERT_TRUE(out && out->open(p, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, z.data()));
    out->close();
    const Image d = read_depth(p);
    EXPECT_EQ(d.width, 6);
    EXPECT_EQ(d.height, 4);
    EXPECT_EQ(d.data, z);
}

TEST_F(FastCodecs, ZipExrFloatsReadAsWrittenInEveryBlockLayout) {
    // ZIP (16-line blocks) and ZIPS (1 line) float channels are inflated by deepsea itself with
    // OpenEXR < 3.2 (exr_zip.h); half channels beside them, other compressions and line orders
    // go through OpenEXR. Odd
    // sizes (a last block of 5 lines), a data window away from (0, 0), a half channel before
    // the floats in the file's order, compressible and incompressible (random) values, and
    // both line orders: every case must read back exactly.
    const int W = 37, H = 21;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 100.0f);
    for (const bool random : {false, true}) {
        std::vector<float> pixels(std::size_t(W) * H * 3);
        for (std::size_t i = 0; i < pixels.size(); ++i)
            pixels[i] = random ? u(rng) : 2.0f + 0.01f * float(i % 97) + 0.001f * float(i / 97);
        for (const std::string compression : {"zip", "zips", "piz", "none"}) {
            for (const std::string order : {"increasingY", "decreasingY"}) {
                const std::string p = path("w_" + compression + order + ".exr");
                OIIO::ImageSpec spec(W, H, 3, OIIO::TypeDesc::FLOAT);
                spec.channelformats = {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT,
                                       OIIO::TypeDesc::FLOAT};
                spec.channelnames = {"A", "B", "Z"};
                spec.x = 3;
                spec.y = 5;
                spec.attribute("compression", compression);
                spec.attribute("openexr:lineOrder", order);
                auto out = OIIO::ImageOutput::create(p);
                ASSERT_TRUE(out && out->open(p, spec));
                ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
                out->close();
                const std::string what = compression + " " + order + (random ? " random" : "");
                DepthReadOptions z;
                z.channel = "Z";
                const Image d = read_depth(p, z);
                ASSERT_EQ(d.width, W) << what;
                ASSERT_EQ(d.height, H) << what;
                for (int i = 0; i < W * H; ++i) ASSERT_EQ(d.data[i], pixels[3 * i + 2]) << what;
                z.channel = "B";
                const Image b = read_depth(p, z);
                for (int i = 0; i < W * H; ++i) ASSERT_EQ(b.data[i], pixels[3 * i + 1]) << what;
                // two float channels interleaved, in an order that is not the file's
                const Image zb = read_exr_layer(p, "", {"Z", "B"});
                ASSERT_EQ(zb.channels, 2) << what;
                for (int i = 0; i < W * H; ++i) {
                    ASSERT_EQ(zb.data[2 * i], pixels[3 * i + 2]) << what;
                    ASSERT_EQ(zb.data[2 * i + 1], pixels[3 * i + 1]) << what;
                }
                z.channel = "A";  // half: through OpenEXR
                const Image a = read_depth(p, z);
                for (int i = 0; i < W * H; ++i)
                    ASSERT_EQ(a.data[i], float(Imath::half(pixels[3 * i]))) << what;
            }
        }
    }
}

TEST_F(FastCodecs, ReadsReuseTheImagesStorage) {
    write_color(path("a.png"), probe_image(40, 30), 8);
    Image img;
    read_color(path("a.png"), img);
    const float* before = img.data.data();
    read_color(path("a.png"), img);
    EXPECT_EQ(img.data.data(), before);
    EXPECT_EQ(img.data, read_color(path("a.png")).data);
}

/// A PNG written here rather than by a library, to choose what libraries do not: each row's
/// filter (row y gets filter y mod 5, so every kind follows every other) and the IDAT stream
/// split into chunks of `split` bytes. RGB samples (big-endian at 16 bits) from `codes`.
std::string png_with_every_filter(int w, int h, int bits, const std::vector<std::uint16_t>& codes,
                                  std::size_t split) {
    const int bpp = 3 * bits / 8;
    const std::size_t row = std::size_t(w) * bpp;
    std::vector<std::uint8_t> raw(row * h), filtered;
    for (std::size_t i = 0; i < codes.size(); ++i) {
        if (bits == 8) {
            raw[i] = std::uint8_t(codes[i]);
        } else {
            raw[2 * i] = std::uint8_t(codes[i] >> 8);
            raw[2 * i + 1] = std::uint8_t(codes[i]);
        }
    }
    for (int y = 0; y < h; ++y) {
        const int f = y % 5;
        filtered.push_back(std::uint8_t(f));
        for (std::size_t i = 0; i < row; ++i) {
            const int x = raw[y * row + i];
            const int a = i >= std::size_t(bpp) ? raw[y * row + i - bpp] : 0;
            const int b = y > 0 ? raw[(y - 1) * row + i] : 0;
            const int c = y > 0 && i >= std::size_t(bpp) ? raw[(y - 1) * row + i - bpp] : 0;
            const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b),
                      pc = std::abs(p - c);
            const int paeth = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
            const int pred[5] = {0, a, b, (a + b) / 2, paeth};
            filtered.push_back(std::uint8_t(x - pred[f]));
        }
    }
    libdeflate_compressor* z = libdeflate_alloc_compressor(6);
    std::vector<std::uint8_t> stream(libdeflate_zlib_compress_bound(z, filtered.size()));
    stream.resize(libdeflate_zlib_compress(z, filtered.data(), filtered.size(), stream.data(),
                                           stream.size()));
    libdeflate_free_compressor(z);
    std::string png("\x89PNG\r\n\x1a\n", 8);
    const auto chunk = [&](const char* type, const std::uint8_t* data, std::size_t n) {
        std::string c;
        for (const int s : {24, 16, 8, 0}) c += char(std::uint32_t(n) >> s);
        c.append(type, 4);
        c.append(reinterpret_cast<const char*>(data), n);
        const std::uint32_t crc = libdeflate_crc32(0, c.data() + 4, n + 4);
        for (const int s : {24, 16, 8, 0}) c += char(crc >> s);
        png += c;
    };
    std::uint8_t ihdr[13] = {0,
                             0,
                             std::uint8_t(w >> 8),
                             std::uint8_t(w),
                             0,
                             0,
                             std::uint8_t(h >> 8),
                             std::uint8_t(h),
                             std::uint8_t(bits),
                             2,
                             0,
                             0,
                             0};
    chunk("IHDR", ihdr, 13);
    const std::uint8_t text[] = "Comment\0between";
    chunk("tEXt", text, sizeof text - 1);
    for (std::size_t at = 0; at < stream.size(); at += split) {
        chunk("IDAT", stream.data() + at, std::min(split, stream.size() - at));
    }
    chunk("IEND", nullptr, 0);
    return png;
}

TEST_F(FastCodecs, PngsWithEveryRowFilterDecodeAsOpenImageIODecodesThem) {
    // Noise (left, up and up-left all matter) at 8 and 16 bits, in one IDAT chunk or many:
    // the colour codes of read_frame_color are OpenImageIO's (libpng's) samples.
    std::mt19937 rng(7);
    for (const int bits : {8, 16}) {
        for (const std::size_t split : {std::size_t(1) << 30, std::size_t(97)}) {
            const int w = 37, h = 23;
            std::vector<std::uint16_t> codes(std::size_t(3) * w * h);
            for (auto& c : codes) c = std::uint16_t(rng() % (bits == 8 ? 256 : 65536));
            const std::string p = path("filters" + std::to_string(bits) + "-" +
                                       std::to_string(split % 1000) + ".png");
            test::write_bytes(p, png_with_every_filter(w, h, bits, codes, split));
            Frame frame;
            read_frame_color(p, frame);
            ASSERT_EQ(frame.codes.bits, bits) << p;
            if (bits == 8) {
                EXPECT_EQ(frame.codes.rgb8, oiio_pixels<std::uint8_t>(p, OIIO::TypeDesc::UINT8))
                    << p;
                EXPECT_EQ(
                    std::vector<std::uint16_t>(frame.codes.rgb8.begin(), frame.codes.rgb8.end()),
                    codes);
            } else {
                EXPECT_EQ(frame.codes.rgb16, oiio_pixels<std::uint16_t>(p, OIIO::TypeDesc::UINT16))
                    << p;
                EXPECT_EQ(frame.codes.rgb16, codes);
            }
        }
    }
}

TEST_F(FastCodecs, FrameColourKeepsPngAndJpegAsCodesThatDecodeToReadColour) {
    write_color(path("a.png"), probe_image(40, 30), 8);
    write_color(path("a16.png"), probe_image(40, 30), 16);
    write_color(path("a.jpg"), probe_image(40, 30), 8);
    write_color(path("a.tif"), probe_image(40, 30), 8);
    Frame frame;
    for (const std::string f : {"a.png", "a16.png", "a.jpg"}) {
        read_frame_color(path(f), frame);
        ASSERT_TRUE(frame.coded()) << f;
        EXPECT_TRUE(frame.rgb.empty()) << f;
        EXPECT_EQ(frame.color_width(), 40) << f;
        EXPECT_EQ(frame.color_height(), 30) << f;
        EXPECT_EQ(frame.codes.bits, f == "a16.png" ? 16 : 8) << f;
        std::vector<float> decoded(3 * 40 * 30);
        if (frame.codes.bits == 16) {
            ASSERT_EQ(frame.codes.rgb16.size(), decoded.size());
            srgb_decode(frame.codes.rgb16.data(), decoded.size(), decoded.data());
        } else {
            ASSERT_EQ(frame.codes.rgb8.size(), decoded.size());
            srgb_decode(frame.codes.rgb8.data(), decoded.size(), decoded.data());
        }
        EXPECT_EQ(decoded, read_color(path(f)).data) << f;
    }
    // other formats arrive as float, and the codes of the frame before are dropped
    read_frame_color(path("a.tif"), frame);
    EXPECT_FALSE(frame.coded());
    EXPECT_EQ(frame.color_width(), 40);
    EXPECT_EQ(frame.rgb.data, read_color(path("a.tif")).data);
    read_frame_color(path("a.png"), frame);
    EXPECT_TRUE(frame.coded());
    EXPECT_THROW(read_frame_color(path("none.png"), frame), IoError);
}

}  // namespace
}  // namespace deepsea
