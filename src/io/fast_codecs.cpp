// PNG through libspng (decode) and libdeflate (encode), JPEG through libjpeg-turbo, EXR through
// OpenEXR: the formats datasets use, without OpenImageIO's per-call overhead and float
// conversions (docs/runtime.md, "Where the time goes").

#include "fast_codecs.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <fcntl.h>
#include <libdeflate.h>
#include <spng.h>
#include <sys/stat.h>
#include <unistd.h>

// jpeglib.h needs FILE and size_t declared first.
#include <cstdio>
#include <cstdlib>
// clang-format off
#include <jpeglib.h>
// clang-format on

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <exception>
#include <mutex>
#include <new>
#include <thread>
#include <utility>

#include "buffer_pool.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "exif.h"
#include "file_checks.h"

namespace deepsea::io_detail {

namespace {

/// The whole file into `bytes` (its capacity reused from frame to frame).
void read_whole_file(const std::string& path, std::vector<std::uint8_t>& bytes) {
    require_readable(path);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) io_fail(path, std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int e = errno;
        ::close(fd);
        io_fail(path, std::strerror(e));
    }
    if (st.st_size == 0) {
        ::close(fd);
        io_fail(path, "empty file");
    }
    bytes.resize(std::size_t(st.st_size));
    std::size_t got = 0;
    while (got < bytes.size()) {
        const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int e = errno;
            ::close(fd);
            io_fail(path, n == 0 ? std::string("file shrank while reading") : std::strerror(e));
        }
        got += std::size_t(n);
    }
    ::close(fd);
}

/// Creates or truncates `file` and writes all of `bytes`, checking every write and the close
/// (a full disk is an IoError naming `name`). No fsync: as OpenImageIO's writers, which the
/// rename after it makes atomic, not durable.
void write_bytes(const std::string& file, const std::uint8_t* bytes, std::size_t size,
                 const std::string& name) {
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) io_fail(name, std::strerror(errno));
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::write(fd, bytes + done, size - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int e = n < 0 ? errno : ENOSPC;
            ::close(fd);
            io_fail(name, std::string("write failed: ") + std::strerror(e));
        }
        done += std::size_t(n);
    }
    if (::close(fd) != 0) io_fail(name, std::string("write failed: ") + std::strerror(errno));
}

// ---------------------------------------------------------------------------------------------
// PNG decoding (libspng)

struct SpngCtx {
    spng_ctx* ctx = spng_ctx_new(0);
    ~SpngCtx() { spng_ctx_free(ctx); }
};

[[noreturn]] void png_fail(const std::string& path, int err) {
    io_fail(path, std::string("corrupt or truncated PNG (") + spng_strerror(err) + ")");
}

/// Opens `bytes` in `c` and returns its header, its size checked against deepsea's limits.
spng_ihdr png_header(const std::string& path, SpngCtx& c, const std::vector<std::uint8_t>& bytes) {
    if (!c.ctx) io_fail(path, "out of memory");
    // Text and other ancillary chunks are not needed; cap what a hostile file can make libspng
    // keep (the pixels are checked against deepsea's limits below).
    spng_set_chunk_limits(c.ctx, 1 << 24, 1 << 26);
    int err = spng_set_png_buffer(c.ctx, bytes.data(), bytes.size());
    spng_ihdr ihdr{};
    if (!err) err = spng_get_ihdr(c.ctx, &ihdr);
    if (err) png_fail(path, err);
    const int channels = ihdr.color_type == SPNG_COLOR_TYPE_TRUECOLOR         ? 3
                         : ihdr.color_type == SPNG_COLOR_TYPE_TRUECOLOR_ALPHA ? 4
                         : ihdr.color_type == SPNG_COLOR_TYPE_GRAYSCALE_ALPHA ? 2
                         : ihdr.color_type == SPNG_COLOR_TYPE_INDEXED         ? 3
                                                                              : 1;
    check_image_size(ihdr.width, ihdr.height, channels, path);
    check_png_claim(path, ihdr.width, ihdr.height, bytes.size());
    return ihdr;
}

/// A decoder's scratch: the encoded file, and for PNGs the joined IDAT data, the inflated
/// stream of a 16-bit file and its unfiltered rows.
struct DecodeScratch {
    std::vector<std::uint8_t> file, idat, inflated, rows16;
};
BufferPool<DecodeScratch> decode_scratch;

struct Decompressor {
    libdeflate_decompressor* d = libdeflate_alloc_decompressor();
    ~Decompressor() { libdeflate_free_decompressor(d); }
};

std::uint32_t be32_at(const std::uint8_t* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | p[3];
}

#if defined(__SSE2__)
/// PNG's Paeth filter from a row's second pixel on, one pixel (B <= 8 bytes) per step in 16-bit
/// lanes and without branches: the scalar choice between left, up and up-left mispredicts on
/// real images (12 ns a pixel on the Paeth rows of the authors' frames, 3.8 ns here). Each
/// step loads 8 bytes from the pixel's start, so it stops where that would pass the row's end
/// (the scalar loop does the rest), and stores exactly the pixel's B bytes: in place, the next
/// pixel's filtered bytes lie just after it. The first pixel must be done. Returns the first
/// byte not done.
template <int B>
std::size_t paeth_sse2(const std::uint8_t* x, const std::uint8_t* up, std::uint8_t* out,
                       std::size_t n) {
    static_assert(B <= 8);
    const __m128i zero = _mm_setzero_si128(), bytes = _mm_set1_epi16(0xff);
    std::uint8_t pixel[8] = {};
    const auto load = [&](const std::uint8_t* p) {
        return _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)), zero);
    };
    const auto load_pixel = [&](const std::uint8_t* p) {
        std::memcpy(pixel, p, B);
        return load(pixel);
    };
    const auto abs16 = [](__m128i v) {
        return _mm_max_epi16(v, _mm_sub_epi16(_mm_setzero_si128(), v));
    };
    __m128i left = load_pixel(out), upleft = load_pixel(up);
    std::size_t i = B;
    for (; i + 8 <= n; i += B) {
        const __m128i above = load(up + i);
        const __m128i bc = _mm_sub_epi16(above, upleft), ac = _mm_sub_epi16(left, upleft);
        const __m128i pa = abs16(bc), pb = abs16(ac), pc = abs16(_mm_add_epi16(bc, ac));
        // left if pa <= pb and pa <= pc; else up if pb <= pc; else up-left
        const __m128i not_left = _mm_or_si128(_mm_cmpgt_epi16(pa, pb), _mm_cmpgt_epi16(pa, pc));
        const __m128i not_up = _mm_cmpgt_epi16(pb, pc);
        const __m128i other =
            _mm_or_si128(_mm_and_si128(not_up, upleft), _mm_andnot_si128(not_up, above));
        const __m128i pred =
            _mm_or_si128(_mm_and_si128(not_left, other), _mm_andnot_si128(not_left, left));
        left = _mm_and_si128(_mm_add_epi16(load(x + i), pred), bytes);
        upleft = above;
        _mm_storel_epi64(reinterpret_cast<__m128i*>(pixel), _mm_packus_epi16(left, zero));
        std::memcpy(out + i, pixel, B);
    }
    return i;
}
#endif

/// Undoes PNG's row filters: `rows` rows of n bytes, each after its filter byte in src, into
/// dst (rows of n bytes, the row above read back from dst); bpp bytes per pixel. False for a
/// filter type PNG does not define. dst may be src itself: each byte is written below the
/// bytes still to be read.
bool unfilter_rows(const std::uint8_t* src, int rows, std::size_t n, int bpp, std::uint8_t* dst) {
    thread_local std::vector<std::uint8_t> zeros;
    zeros.assign(n, 0);
    for (int y = 0; y < rows; ++y) {
        const std::uint8_t* in = src + std::size_t(y) * (n + 1);
        const std::uint8_t* up = y ? dst + std::size_t(y - 1) * n : zeros.data();
        std::uint8_t* out = dst + std::size_t(y) * n;
        const std::uint8_t* x = in + 1;
        const std::size_t b = std::size_t(bpp);
        switch (in[0]) {
            case 0:
                std::memmove(out, x, n);
                break;
            case 1:  // sub: the byte one pixel to the left
                for (std::size_t i = 0; i < std::min(b, n); ++i) out[i] = x[i];
                for (std::size_t i = b; i < n; ++i) out[i] = std::uint8_t(x[i] + out[i - b]);
                break;
            case 2:  // up
                for (std::size_t i = 0; i < n; ++i) out[i] = std::uint8_t(x[i] + up[i]);
                break;
            case 3:  // average of left and up
                for (std::size_t i = 0; i < std::min(b, n); ++i)
                    out[i] = std::uint8_t(x[i] + (up[i] >> 1));
                for (std::size_t i = b; i < n; ++i)
                    out[i] = std::uint8_t(x[i] + ((unsigned(out[i - b]) + up[i]) >> 1));
                break;
            case 4: {  // Paeth: whichever of left, up and up-left is nearest left + up - up-left
                for (std::size_t i = 0; i < std::min(b, n); ++i)
                    out[i] = std::uint8_t(x[i] + up[i]);
                std::size_t i = b;
#if defined(__SSE2__)
                if (bpp == 3) i = paeth_sse2<3>(x, up, out, n);
                if (bpp == 6) i = paeth_sse2<6>(x, up, out, n);
#endif
                for (; i < n; ++i) {
                    const int a = out[i - b], c = up[i - b], u = up[i];
                    const int pa = std::abs(u - c), pb = std::abs(a - c),
                              pc = std::abs(a + u - 2 * c);
                    const int p = pa <= pb && pa <= pc ? a : pb <= pc ? u : c;
                    out[i] = std::uint8_t(x[i] + p);
                }
                break;
            }
            default:
                return false;
        }
    }
    return true;
}

/// decode_png_rgb's path for the commonest dataset PNG, RGB at 8 or 16 bits and not interlaced:
/// the IDAT stream inflated whole by libdeflate (about twice zlib's speed; libspng inflates
/// with zlib) and unfiltered straight into `out`. False, for libspng to decode the file or
/// name its fault, for anything else: another colour type, a critical chunk with a bad CRC or
/// of another kind, IDAT chunks apart, no IEND, a stream that is not the image's size.
bool decode_png_rgb_direct(DecodeScratch& s, const spng_ihdr& ihdr, PngRgb& out) {
    const std::vector<std::uint8_t>& file = s.file;
    if (ihdr.color_type != SPNG_COLOR_TYPE_TRUECOLOR || ihdr.interlace_method != 0 ||
        (ihdr.bit_depth != 8 && ihdr.bit_depth != 16)) {
        return false;
    }
    // The IDAT chunks' data: used where it lies when there is one chunk (as deepsea writes
    // them), else joined.
    std::vector<std::pair<const std::uint8_t*, std::size_t>> idat_data;
    bool ended = false, idat_closed = false;
    for (std::size_t at = 8; !ended;) {
        if (file.size() - at < 12) return false;
        const std::uint32_t len = be32_at(file.data() + at);
        if (len > file.size() - at - 12) return false;
        const std::uint8_t* type = file.data() + at + 4;
        const std::uint8_t* data = type + 4;
        const bool critical = !(type[0] & 0x20);
        if (critical && libdeflate_crc32(0, type, len + 4) != be32_at(data + len)) return false;
        const bool idat = std::memcmp(type, "IDAT", 4) == 0;
        if (idat) {
            if (idat_closed) return false;
            idat_data.emplace_back(data, len);
        } else {
            idat_closed = !idat_data.empty();
            ended = std::memcmp(type, "IEND", 4) == 0;
            if (critical && !ended && std::memcmp(type, "IHDR", 4) != 0 &&
                std::memcmp(type, "PLTE", 4) != 0) {
                return false;
            }
        }
        at += std::size_t(len) + 12;
    }
    if (idat_data.empty()) return false;
    const int w = int(ihdr.width), h = int(ihdr.height), bytes = ihdr.bit_depth / 8;
    const std::size_t row = std::size_t(w) * 3 * bytes, expect = (row + 1) * std::size_t(h);
    thread_local Decompressor inflater;
    if (!inflater.d) return false;
    // 8 bits: inflated into the codes' own buffer and unfiltered there (no second image).
    std::vector<std::uint8_t>& inflated = bytes == 1 ? out.rgb8 : s.inflated;
    inflated.resize(expect);
    std::size_t got = 0;
    const std::uint8_t* stream = idat_data[0].first;
    std::size_t stream_size = idat_data[0].second;
    if (idat_data.size() > 1) {
        s.idat.clear();
        for (const auto& [p, n] : idat_data) s.idat.insert(s.idat.end(), p, p + n);
        stream = s.idat.data();
        stream_size = s.idat.size();
    }
    if (libdeflate_zlib_decompress(inflater.d, stream, stream_size, inflated.data(), expect,
                                   &got) != LIBDEFLATE_SUCCESS ||
        got != expect) {
        return false;
    }
    const std::size_t n = std::size_t(w) * h * 3;
    if (bytes == 1) {
        if (!unfilter_rows(out.rgb8.data(), h, row, 3, out.rgb8.data())) return false;
        out.rgb8.resize(n);
        out.bits = 8;
    } else {
        s.rows16.resize(row * h);
        if (!unfilter_rows(s.inflated.data(), h, row, 6, s.rows16.data())) return false;
        out.rgb16.resize(n);
        const std::uint8_t* b = s.rows16.data();
        for (std::size_t i = 0; i < n; ++i)
            out.rgb16[i] = std::uint16_t(b[2 * i] << 8 | b[2 * i + 1]);
        out.bits = 16;
    }
    out.width = w;
    out.height = h;
    return true;
}

thread_local std::vector<std::uint16_t> t_rgba16;
thread_local std::vector<std::uint8_t> t_rgba8;

}  // namespace

void decode_png_rgb(const std::string& path, PngRgb& out) {
    const auto scratch = decode_scratch.take();
    read_whole_file(path, scratch->file);
    SpngCtx c;
    const spng_ihdr ihdr = png_header(path, c, scratch->file);
    if (decode_png_rgb_direct(*scratch, ihdr, out)) return;
    out.width = int(ihdr.width);
    out.height = int(ihdr.height);
    const std::size_t n = std::size_t(out.width) * out.height;
    int err = 0;
    if (ihdr.bit_depth == 16) {
        out.bits = 16;
        // libspng converts every 16-bit colour type to RGBA16 (host order); alpha is dropped.
        t_rgba16.resize(n * 4);
        err = spng_decode_image(c.ctx, t_rgba16.data(), n * 8, SPNG_FMT_RGBA16, 0);
        if (err) png_fail(path, err);
        out.rgb16.resize(n * 3);
        for (std::size_t i = 0; i < n; ++i) {
            out.rgb16[i * 3 + 0] = t_rgba16[i * 4 + 0];
            out.rgb16[i * 3 + 1] = t_rgba16[i * 4 + 1];
            out.rgb16[i * 3 + 2] = t_rgba16[i * 4 + 2];
        }
    } else if (ihdr.color_type == SPNG_COLOR_TYPE_GRAYSCALE_ALPHA ||
               ihdr.color_type == SPNG_COLOR_TYPE_TRUECOLOR_ALPHA) {
        // With alpha: through RGBA8 (libspng's RGB8 from grey + alpha is not the grey).
        out.bits = 8;
        t_rgba8.resize(n * 4);
        err = spng_decode_image(c.ctx, t_rgba8.data(), n * 4, SPNG_FMT_RGBA8, 0);
        if (err) png_fail(path, err);
        out.rgb8.resize(n * 3);
        for (std::size_t i = 0; i < n; ++i) {
            out.rgb8[i * 3 + 0] = t_rgba8[i * 4 + 0];
            out.rgb8[i * 3 + 1] = t_rgba8[i * 4 + 1];
            out.rgb8[i * 3 + 2] = t_rgba8[i * 4 + 2];
        }
    } else {
        out.bits = 8;
        out.rgb8.resize(n * 3);
        err = spng_decode_image(c.ctx, out.rgb8.data(), n * 3, SPNG_FMT_RGB8, 0);
        if (err) png_fail(path, err);
    }
}

bool decode_png_grey16(const std::string& path, int& width, int& height,
                       std::vector<std::uint16_t>& values) {
    const auto scratch = decode_scratch.take();
    read_whole_file(path, scratch->file);
    SpngCtx c;
    const spng_ihdr ihdr = png_header(path, c, scratch->file);
    if (ihdr.color_type != SPNG_COLOR_TYPE_GRAYSCALE || ihdr.bit_depth != 16) return false;
    width = int(ihdr.width);
    height = int(ihdr.height);
    const std::size_t n = std::size_t(width) * height;
    values.resize(n);
    // SPNG_FMT_PNG: the file's own layout, in host order (only SPNG_FMT_RAW is big-endian).
    const int err = spng_decode_image(c.ctx, values.data(), n * 2, SPNG_FMT_PNG, 0);
    if (err) png_fail(path, err);
    return true;
}

// ---------------------------------------------------------------------------------------------
// PNG encoding (libdeflate)

namespace {

void put32(std::vector<std::uint8_t>& v, std::uint32_t x) {
    v.push_back(std::uint8_t(x >> 24));
    v.push_back(std::uint8_t(x >> 16));
    v.push_back(std::uint8_t(x >> 8));
    v.push_back(std::uint8_t(x));
}

/// Appends one chunk (length, type, data, CRC of type and data).
void chunk(std::vector<std::uint8_t>& png, const char type[4], const std::uint8_t* data,
           std::size_t size) {
    put32(png, std::uint32_t(size));
    const std::size_t start = png.size();
    png.insert(png.end(), type, type + 4);
    png.insert(png.end(), data, data + size);
    put32(png, libdeflate_crc32(0, png.data() + start, size + 4));
}

struct Compressor {
    libdeflate_compressor* c = libdeflate_alloc_compressor(1);
    ~Compressor() { libdeflate_free_compressor(c); }
};

/// write_png's scratch: the filtered rows and the file being built.
struct EncodeScratch {
    std::vector<std::uint8_t> filtered, png;
};
BufferPool<EncodeScratch> encode_scratch;

}  // namespace

void write_png(const std::string& path, int width, int height, int channels,
               const std::uint8_t* pixels8, const std::uint16_t* pixels16,
               const ImageMetadata& meta) {
    const int bytes = pixels16 ? 2 : 1;
    const std::size_t row = std::size_t(width) * channels * bytes;
    // Filter "up" (each byte minus the one above): the cheapest filter that helps, on rendered
    // frames as small as libpng's adaptive choice at a fraction of the time.
    const auto scratch = encode_scratch.take();
    std::vector<std::uint8_t>& f = scratch->filtered;
    f.resize((row + 1) * height);
    std::vector<std::uint8_t> prev(row, 0), cur(row);
    for (int y = 0; y < height; ++y) {
        if (pixels16) {
            const std::uint16_t* s = pixels16 + std::size_t(y) * width * channels;
            for (std::size_t i = 0; i < row / 2; ++i) {
                cur[2 * i] = std::uint8_t(s[i] >> 8);  // PNG samples are big-endian
                cur[2 * i + 1] = std::uint8_t(s[i]);
            }
        } else {
            std::memcpy(cur.data(), pixels8 + std::size_t(y) * row, row);
        }
        std::uint8_t* d = f.data() + std::size_t(y) * (row + 1);
        d[0] = 2;  // up
        for (std::size_t i = 0; i < row; ++i) d[1 + i] = std::uint8_t(cur[i] - prev[i]);
        std::swap(prev, cur);
    }
    static thread_local Compressor comp;
    if (!comp.c) io_fail(path, "out of memory");
    std::vector<std::uint8_t>& png = scratch->png;
    png.clear();
    static const std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    png.insert(png.end(), sig, sig + 8);
    std::vector<std::uint8_t> ihdr;
    put32(ihdr, std::uint32_t(width));
    put32(ihdr, std::uint32_t(height));
    ihdr.push_back(std::uint8_t(bytes * 8));
    ihdr.push_back(channels == 3 ? 2 : 0);  // truecolour or grey
    ihdr.push_back(0);                      // deflate
    ihdr.push_back(0);                      // adaptive filtering
    ihdr.push_back(0);                      // not interlaced
    chunk(png, "IHDR", ihdr.data(), ihdr.size());
    const std::uint8_t intent = 0;  // sRGB, perceptual
    chunk(png, "sRGB", &intent, 1);
    for (const auto& [name, value] : meta) {
        std::vector<std::uint8_t> text(name.begin(),
                                       name.begin() + std::min<std::size_t>(79, name.size()));
        text.push_back(0);
        text.insert(text.end(), value.begin(), value.end());
        chunk(png, "tEXt", text.data(), text.size());
    }
    // One IDAT chunk holds the whole stream, compressed in place (no copy of the data).
    const std::size_t bound = libdeflate_zlib_compress_bound(comp.c, f.size());
    const std::size_t at = png.size();
    png.resize(at + 8 + bound + 4);
    const std::size_t z =
        libdeflate_zlib_compress(comp.c, f.data(), f.size(), png.data() + at + 8, bound);
    if (z == 0 || z > 0x7fffffff) io_fail(path, "deflate failed");
    std::uint8_t* h = png.data() + at;
    const auto be32 = [](std::uint8_t* d, std::uint32_t x) {
        d[0] = std::uint8_t(x >> 24), d[1] = std::uint8_t(x >> 16), d[2] = std::uint8_t(x >> 8),
        d[3] = std::uint8_t(x);
    };
    be32(h, std::uint32_t(z));
    std::memcpy(h + 4, "IDAT", 4);
    be32(h + 8 + z, libdeflate_crc32(0, h + 4, z + 4));
    png.resize(at + 8 + z + 4);
    chunk(png, "IEND", nullptr, 0);
    write_atomically(
        path, [&](const std::string& tmp) { write_bytes(tmp, png.data(), png.size(), path); });
}

// ---------------------------------------------------------------------------------------------
// JPEG encoding (libjpeg-turbo)

namespace {

struct JpegError {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = {};
};

extern "C" void jpeg_error_exit(j_common_ptr cinfo) {
    auto* e = reinterpret_cast<JpegError*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, e->message);
    std::longjmp(e->jump, 1);
}

extern "C" void jpeg_silent(j_common_ptr, int) {}

}  // namespace

void write_jpeg(const std::string& path, int width, int height, int channels,
                const std::uint8_t* pixels, const ImageMetadata& meta) {
    std::string comment;
    for (const auto& [name, value] : meta) comment += name + "=" + value + "\n";
    unsigned char* buf = nullptr;
    unsigned long size = 0;
    // Plain C structs only between setjmp and longjmp (no destructors skipped).
    jpeg_compress_struct cinfo{};
    JpegError err;
    cinfo.err = jpeg_std_error(&err.mgr);
    err.mgr.error_exit = jpeg_error_exit;
    err.mgr.emit_message = jpeg_silent;
    if (setjmp(err.jump)) {
        jpeg_destroy_compress(&cinfo);
        std::free(buf);
        io_fail(path, std::string("JPEG encoder: ") + err.message);
    }
    jpeg_create_compress(&cinfo);
    jpeg_mem_dest(&cinfo, &buf, &size);
    cinfo.image_width = JDIMENSION(width);
    cinfo.image_height = JDIMENSION(height);
    cinfo.input_components = channels;
    cinfo.in_color_space = channels == 3 ? JCS_RGB : JCS_GRAYSCALE;
    jpeg_set_defaults(&cinfo);  // 4:2:0, JFIF, Huffman tables of the standard
    jpeg_set_quality(&cinfo, 95, TRUE);
    jpeg_start_compress(&cinfo, TRUE);
    if (comment.size() < 65000) {
        jpeg_write_marker(&cinfo, JPEG_COM, reinterpret_cast<const JOCTET*>(comment.data()),
                          unsigned(comment.size()));
    }
    const std::size_t row = std::size_t(width) * channels;
    while (cinfo.next_scanline < cinfo.image_height) {
        JSAMPROW r = const_cast<JSAMPROW>(pixels + cinfo.next_scanline * row);
        jpeg_write_scanlines(&cinfo, &r, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    try {
        write_atomically(path, [&](const std::string& tmp) { write_bytes(tmp, buf, size, path); });
    } catch (...) {
        std::free(buf);
        throw;
    }
    std::free(buf);
}

namespace {

/// Warnings are errors when decoding: libjpeg "warns" of a truncated file or damaged data and
/// fills the rest with grey, which would be rendered as if it were the frame.
extern "C" void jpeg_warning_is_error(j_common_ptr cinfo, int level) {
    if (level < 0) jpeg_error_exit(cinfo);
}

}  // namespace

void decode_jpeg_rgb(const std::string& path, int& width, int& height,
                     std::vector<std::uint8_t>& rgb) {
    const auto scratch = decode_scratch.take();  // before setjmp: only C objects after it
    const std::vector<std::uint8_t>& file = scratch->file;
    read_whole_file(path, scratch->file);
    const int orientation = jpeg_orientation(file.data(), file.size());
    if (orientation != 1) {
        throw InputError(path + ": its EXIF orientation " + std::to_string(orientation) + " (" +
                         describe_orientation(orientation) +
                         ") would turn the colour against the depth, which deepsea pairs pixel "
                         "by pixel as stored; store the frame upright (exiftran -ai) or remove "
                         "the tag");
    }
    jpeg_decompress_struct cinfo{};
    JpegError err;
    cinfo.err = jpeg_std_error(&err.mgr);
    err.mgr.error_exit = jpeg_error_exit;
    err.mgr.emit_message = jpeg_warning_is_error;
    // Only C objects between here and the longjmp; the exception is thrown after it.
    long long w = 0, h = 0;
    if (setjmp(err.jump)) {
        jpeg_destroy_decompress(&cinfo);
        io_fail(path, std::string("corrupt or truncated JPEG (") + err.message + ")");
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, file.data(), static_cast<unsigned long>(file.size()));
    jpeg_read_header(&cinfo, TRUE);
    w = cinfo.image_width;
    h = cinfo.image_height;
    try {
        check_image_size(w, h, 3, path);  // and an ExpectImageSize of the caller's
    } catch (...) {
        jpeg_destroy_decompress(&cinfo);
        throw;
    }
    cinfo.out_color_space = JCS_RGB;  // grey and YCbCr alike; CMYK is refused below
    if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
        jpeg_destroy_decompress(&cinfo);
        io_fail(path, "CMYK JPEG is not supported");
    }
    jpeg_start_decompress(&cinfo);
    width = int(w);
    height = int(h);
    rgb.resize(std::size_t(width) * height * 3);
    while (cinfo.output_scanline < cinfo.output_height) {
        JSAMPROW r = rgb.data() + std::size_t(cinfo.output_scanline) * width * 3;
        jpeg_read_scanlines(&cinfo, &r, 1);
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
}

// ---------------------------------------------------------------------------------------------
// EXR (OpenEXR)

namespace {

/// OpenEXR's global thread pool, sized once to the cores (it is separate from TBB's: its
/// threads mostly wait on zlib/PIZ work of one file at a time).
int exr_threads() {
    static std::once_flag once;
    static int n = 1;
    std::call_once(once, [] {
        n = int(std::max(1u, std::min(4u, std::thread::hardware_concurrency())));
        if (Imf::globalThreadCount() < n) Imf::setGlobalThreadCount(n);
    });
    return n;
}

}  // namespace

void write_exr(const std::string& path, int width, int height,
               const std::vector<ExrChannel>& channels, bool half, const std::string& compression,
               const ImageMetadata& meta) {
    const int threads = exr_threads();
    Imf::Header header(width, height);
    header.compression() = compression == "piz" ? Imf::PIZ_COMPRESSION : Imf::ZIP_COMPRESSION;
    for (const auto& [name, value] : meta) header.insert(name, Imf::StringAttribute(value));
    Imf::FrameBuffer fb;
    const std::size_t n = std::size_t(width) * height, nc = channels.size();
    // Float channels are written straight from the caller's images; half ones from one
    // interleaved half copy (OpenEXR's writer does not convert float slices to half).
    thread_local std::vector<Imath::half> halves;
    if (half) halves.resize(n * nc);
    for (std::size_t k = 0; k < nc; ++k) {
        const ExrChannel& c = channels[k];
        header.channels().insert(c.name, Imf::Channel(half ? Imf::HALF : Imf::FLOAT));
        if (half) {
            Imath::half* h = halves.data() + k;
            for (std::size_t i = 0; i < n; ++i) h[i * nc] = Imath::half(c.base[i * c.stride]);
            fb.insert(c.name,
                      Imf::Slice(Imf::HALF, reinterpret_cast<char*>(h), sizeof(Imath::half) * nc,
                                 sizeof(Imath::half) * nc * std::size_t(width)));
        } else {
            fb.insert(c.name,
                      Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(c.base)),
                                 sizeof(float) * c.stride,
                                 sizeof(float) * c.stride * std::size_t(width)));
        }
    }
    write_atomically(path, [&](const std::string& tmp) {
        try {
            Imf::OutputFile out(tmp.c_str(), header, threads);
            out.setFrameBuffer(fb);
            out.writePixels(height);
        } catch (const Error&) {
            throw;
        } catch (const std::bad_alloc&) {
            throw;  // out of memory, not a damaged file
        } catch (const std::exception& e) {
            io_fail(path, e.what());
        }
    });
}

struct ExrReader::Impl {
    std::unique_ptr<Imf::InputFile> file;
    int x0 = 0, y0 = 0;
};

ExrReader::ExrReader(const std::string& path) : m_impl(new Impl), m_path(path) {
    require_readable(path);
    check_exr_header(path);
    try {
        m_impl->file = std::make_unique<Imf::InputFile>(path.c_str(), exr_threads());
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        io_fail(path, e.what());
    }
    const Imf::Header& h = m_impl->file->header();
    const auto& dw = h.dataWindow();
    const long long w = (long long)dw.max.x - dw.min.x + 1, hh = (long long)dw.max.y - dw.min.y + 1;
    int n = 0;
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
        m_channels.push_back(it.name());
        m_float.push_back(it.channel().type != Imf::UINT);
        ++n;
        if (n > kMaxImageChannels) break;
    }
    check_image_size(w, hh, n, path);
    // OpenEXR lists channels alphabetically; OpenImageIO (and so deepsea's messages until
    // now) lists each layer's R, G, B, A first: keep that order.
    const auto rank = [](const std::string& name) {
        const std::size_t dot = name.rfind('.');
        const std::string suffix = dot == std::string::npos ? name : name.substr(dot + 1);
        static const char* order[] = {"R", "G", "B", "A"};
        for (int i = 0; i < 4; ++i)
            if (suffix == order[i]) return i;
        return 4;
    };
    const auto layer = [](const std::string& name) {
        const std::size_t dot = name.rfind('.');
        return dot == std::string::npos ? std::string() : name.substr(0, dot);
    };
    std::vector<std::size_t> idx(m_channels.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    // Ties keep the file's order. Not std::stable_sort: under clang 14 + ASan its temporary
    // buffer (libstdc++ 12) is reported as an alloc-dealloc mismatch.
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
        const std::string la = layer(m_channels[a]), lb = layer(m_channels[b]);
        if (la != lb) return la < lb;
        const int ra = rank(m_channels[a]), rb = rank(m_channels[b]);
        return ra != rb ? ra < rb : a < b;
    });
    std::vector<std::string> names;
    std::vector<bool> floats;
    for (std::size_t i : idx) names.push_back(m_channels[i]), floats.push_back(m_float[i]);
    m_channels = std::move(names);
    m_float = std::move(floats);
    m_width = int(w);
    m_height = int(hh);
    m_impl->x0 = dw.min.x;
    m_impl->y0 = dw.min.y;
}

ExrReader::~ExrReader() = default;

namespace {

/// Undoes OpenEXR's ZIP preprocessing of one inflated block of n bytes: the byte predictor
/// (each byte stored as its difference from the one before, plus 128), then the split into
/// halves (bytes 0, 2, 4, .. first, then 1, 3, 5, ..). `in` is overwritten with the prefix
/// sums; `out` gets the block as it was. The predictor is a running sum over bytes: kept in
/// a register (and, with SSE2, summed 16 bytes at a time), never read back from memory.
void unzip_block(unsigned char* __restrict in, std::size_t n, unsigned char* __restrict out) {
    if (n == 0) return;
    std::size_t i = 1;
    unsigned char run = in[0];
#if defined(__SSE2__)
    const __m128i bias = _mm_set1_epi8(char(-128));
    __m128i carry = _mm_set1_epi8(char(run));
    for (; i + 16 <= n; i += 16) {
        __m128i x = _mm_sub_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in + i)), bias);
        x = _mm_add_epi8(x, _mm_slli_si128(x, 1));
        x = _mm_add_epi8(x, _mm_slli_si128(x, 2));
        x = _mm_add_epi8(x, _mm_slli_si128(x, 4));
        x = _mm_add_epi8(x, _mm_slli_si128(x, 8));
        x = _mm_add_epi8(x, carry);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(in + i), x);
        // byte 15 to every byte: bytes 8..15 doubled into words, word 7 to the high words,
        // then dword 3 to every dword
        carry = _mm_shuffle_epi32(_mm_shufflehi_epi16(_mm_unpackhi_epi8(x, x), 0xff), 0xff);
    }
    run = in[i - 1];
#endif
    for (; i < n; ++i) {
        run = (unsigned char)(run + in[i] - 128);
        in[i] = run;
    }
    const std::size_t half = n / 2;
    const unsigned char* lo = in;
    const unsigned char* hi = in + (n + 1) / 2;
    std::size_t k = 0;
#if defined(__SSE2__)
    for (; k + 16 <= half; k += 16) {
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lo + k));
        const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(hi + k));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * k), _mm_unpacklo_epi8(a, b));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * k + 16), _mm_unpackhi_epi8(a, b));
    }
#endif
    for (; k < half; ++k) {
        out[2 * k] = lo[k];
        out[2 * k + 1] = hi[k];
    }
    if (n % 2) out[n - 1] = lo[half];
}

/// A scanline file compressed with ZIP (16 lines a block) or ZIPS (1) whose chosen channels
/// are all 32-bit float, unsampled (a depth map as deepsea and most renderers write it): its
/// blocks are read raw through OpenEXR and inflated by libdeflate in parallel, then undone as
/// OpenEXR's zip compressor does them (a byte predictor, then the two halves interleaved).
/// OpenEXR 3.1 inflates with zlib, at about half libdeflate's speed. Returns false, having
/// read nothing, for every other file (OpenEXR's readPixels reads those).
bool read_zip_floats(Imf::InputFile& file, const std::string& path,
                     const std::vector<std::string>& names, int width, int height, int y0,
                     float* dst) {
    const Imf::Header& h = file.header();
    if (h.hasTileDescription()) return false;
    const Imf::Compression compression = h.compression();
    if (compression != Imf::ZIP_COMPRESSION && compression != Imf::ZIPS_COMPRESSION) return false;
    const int lines = compression == Imf::ZIP_COMPRESSION ? 16 : 1;
    // Each line of a block holds every channel's samples in turn, in the file's (name) order.
    std::size_t line_bytes = 0;
    std::vector<std::size_t> offset(names.size(), std::size_t(-1));
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
        const Imf::Channel& ch = it.channel();
        if (ch.xSampling != 1 || ch.ySampling != 1) return false;
        const std::size_t size = ch.type == Imf::HALF ? 2 : 4;
        for (std::size_t c = 0; c < names.size(); ++c) {
            if (names[c] != it.name()) continue;
            if (ch.type != Imf::FLOAT) return false;
            offset[c] = line_bytes;
        }
        line_bytes += size * std::size_t(width);
    }
    for (const std::size_t o : offset)
        if (o == std::size_t(-1)) return false;

    const int blocks = (height + lines - 1) / lines;
    const std::size_t block_bytes = line_bytes * std::size_t(lines);
    // The compressed blocks of a group one after the other (OpenEXR reads up to a whole
    // block's uncompressed size into the place it is given: room for that is kept at the end).
    // Groups of about 2 MB of pixels are read, then inflated in parallel, so that what is held
    // at once is a group's compressed data, not the file's (10 MB for a 1080p float depth).
    struct Packed {
        std::vector<char> bytes;
        std::vector<std::size_t> start;
    };
    static BufferPool<Packed> pool;
    const auto lease = pool.take();
    std::vector<char>& packed = lease->bytes;
    std::vector<std::size_t>& start = lease->start;
    const int group = std::max(1, int((std::size_t(2) << 20) / block_bytes));
    std::mutex mutex;
    std::string error;
    const std::size_t nc = names.size(), w = std::size_t(width);
    for (int g0 = 0; g0 < blocks && error.empty(); g0 += group) {
        const int g1 = std::min(blocks, g0 + group);
        start.assign(std::size_t(g1 - g0) + 1, 0);
        try {
            for (int b = g0; b < g1; ++b) {
                const std::size_t at = start[b - g0];
                if (packed.size() < at + block_bytes) packed.resize(at + block_bytes);
                int size = int(block_bytes);
                file.rawPixelDataToBuffer(y0 + b * lines, packed.data() + at, size);
                if (size < 0 || std::size_t(size) > block_bytes)
                    io_fail(path,
                            "block at line " + std::to_string(y0 + b * lines) + " is too large");
                start[b - g0 + 1] = at + std::size_t(size);
            }
        } catch (const Error&) {
            throw;
        } catch (const std::bad_alloc&) {
            throw;  // out of memory, not a damaged file
        } catch (const std::exception& e) {
            io_fail(path, e.what());
        }
        tbb::this_task_arena::isolate([&] {
            tbb::parallel_for(g0, g1, [&](int b) {
                thread_local Decompressor inflater;
                thread_local std::vector<unsigned char> inflated, raw;
                const int n = std::min(lines, height - b * lines);
                const std::size_t expect = line_bytes * std::size_t(n);
                const auto* src =
                    reinterpret_cast<const unsigned char*>(packed.data() + start[b - g0]);
                const std::size_t got = start[b - g0 + 1] - start[b - g0];
                const unsigned char* data = src;  // a block that would not shrink is stored as is
                if (got < expect) {
                    inflated.resize(expect);
                    std::size_t out = 0;
                    if (libdeflate_zlib_decompress(inflater.d, src, got, inflated.data(), expect,
                                                   &out) != LIBDEFLATE_SUCCESS ||
                        out != expect) {
                        std::lock_guard<std::mutex> lock(mutex);
                        error = "corrupt ZIP block at line " + std::to_string(y0 + b * lines);
                        return;
                    }
                    // One float channel alone in the file: its lines are the destination's rows.
                    const bool direct = nc == 1 && line_bytes == 4 * w;
                    if (!direct) raw.resize(expect);
                    unsigned char* to =
                        direct ? reinterpret_cast<unsigned char*>(dst + std::size_t(b) * lines * w)
                               : raw.data();
                    unzip_block(inflated.data(), expect, to);
                    if (direct) return;
                    data = raw.data();
                } else if (got != expect) {
                    std::lock_guard<std::mutex> lock(mutex);
                    error = "block at line " + std::to_string(y0 + b * lines) + " has " +
                            std::to_string(got) + " bytes, expected " + std::to_string(expect);
                    return;
                }
                for (int l = 0; l < n; ++l) {
                    const std::size_t y = std::size_t(b) * lines + l;
                    for (std::size_t c = 0; c < nc; ++c) {
                        const unsigned char* in = data + line_bytes * l + offset[c];
                        float* out = dst + y * w * nc + c;
                        if (nc == 1) {
                            std::memcpy(out, in, 4 * w);  // little-endian, as the file
                        } else {
                            for (std::size_t x = 0; x < w; ++x)
                                std::memcpy(out + x * nc, in + 4 * x, 4);
                        }
                    }
                }
            });
        });
    }
    if (!error.empty()) io_fail(path, error);
    return true;
}

}  // namespace

void ExrReader::read(const std::vector<int>& channels, float* dst) {
    static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "EXR samples are little-endian");
    std::vector<std::string> names;
    for (const int c : channels) names.push_back(m_channels[c]);
    if (read_zip_floats(*m_impl->file, m_path, names, m_width, m_height, m_impl->y0, dst)) return;
    const std::size_t w = std::size_t(m_width), nc = channels.size();
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < nc; ++c) {
        // The frame buffer's origin is the data window's, so that dst holds it from its first
        // pixel.
        char* base = reinterpret_cast<char*>(dst + c - std::ptrdiff_t(nc) * m_impl->x0 -
                                             std::ptrdiff_t(nc * w) * m_impl->y0);
        fb.insert(m_channels[channels[c]],
                  Imf::Slice(Imf::FLOAT, base, sizeof(float) * nc, sizeof(float) * nc * w));
    }
    try {
        m_impl->file->setFrameBuffer(fb);
        m_impl->file->readPixels(m_impl->y0, m_impl->y0 + m_height - 1);
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        io_fail(m_path, e.what());
    }
}

}  // namespace deepsea::io_detail
