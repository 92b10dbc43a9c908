// PNG decoding through libspng, and for the commonest dataset PNGs (RGB at 8 or 16 bits, not
// interlaced) the stream inflated by ISA-L and unfiltered here.

#include <isa-l.h>
#include <libdeflate.h>
#include <spng.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <utility>

#include "byte_simd.h"
#include "codec_files.h"
#include "deepsea/core/error.h"
#include "fast_codecs.h"
#include "file_checks.h"

namespace deepsea::io_detail {

namespace {

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

std::uint32_t be32_at(const std::uint8_t* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | p[3];
}

/// ISA-L's inflate state (85 KB), kept from frame to frame by the threads that decode.
BufferPool<inflate_state> inflate_states;

/// Inflates the zlib stream `in` into exactly `size` bytes at `out`, its Adler-32 checked;
/// false for a stream that is damaged, needs a preset dictionary, or does not end at `size`.
/// ISA-L, not libdeflate: a PNG's rows are mostly literals with short codes, which ISA-L's
/// tables decode several at a time (docs/runtime.md, "Image I/O", has the measurements).
bool inflate_zlib(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out,
                  std::size_t size) {
    if (in_size > UINT32_MAX || size > UINT32_MAX) return false;
    const auto state = inflate_states.take();
    isal_inflate_init(&*state);
    state->crc_flag = ISAL_ZLIB;
    state->next_in = const_cast<std::uint8_t*>(in);
    state->avail_in = std::uint32_t(in_size);
    state->next_out = out;
    state->avail_out = std::uint32_t(size);
    return isal_inflate(&*state) == ISAL_DECOMP_OK && state->block_state == ISAL_BLOCK_FINISH &&
           state->total_out == size;
}

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
/// the IDAT stream inflated whole by ISA-L (inflate_zlib; libspng inflates with zlib) and
/// unfiltered straight into `out`. False, for libspng to decode the file or
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
    // 8 bits: inflated into the codes' own buffer and unfiltered there (no second image).
    std::vector<std::uint8_t>& inflated = bytes == 1 ? out.rgb8 : s.inflated;
    inflated.resize(expect);
    const std::uint8_t* stream = idat_data[0].first;
    std::size_t stream_size = idat_data[0].second;
    if (idat_data.size() > 1) {
        s.idat.clear();
        for (const auto& [p, n] : idat_data) s.idat.insert(s.idat.end(), p, p + n);
        stream = s.idat.data();
        stream_size = s.idat.size();
    }
    if (!inflate_zlib(stream, stream_size, inflated.data(), expect)) return false;
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

/// The RGB of n RGBA pixels.
template <class T>
void drop_alpha(const std::vector<T>& rgba, std::size_t n, std::vector<T>& rgb) {
    rgb.resize(n * 3);
    for (std::size_t i = 0; i < n; ++i) {
        rgb[i * 3 + 0] = rgba[i * 4 + 0];
        rgb[i * 3 + 1] = rgba[i * 4 + 1];
        rgb[i * 3 + 2] = rgba[i * 4 + 2];
    }
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
        drop_alpha(t_rgba16, n, out.rgb16);
    } else if (ihdr.color_type == SPNG_COLOR_TYPE_GRAYSCALE_ALPHA ||
               ihdr.color_type == SPNG_COLOR_TYPE_TRUECOLOR_ALPHA) {
        // With alpha: through RGBA8 (libspng's RGB8 from grey + alpha is not the grey).
        out.bits = 8;
        t_rgba8.resize(n * 4);
        err = spng_decode_image(c.ctx, t_rgba8.data(), n * 4, SPNG_FMT_RGBA8, 0);
        if (err) png_fail(path, err);
        drop_alpha(t_rgba8, n, out.rgb8);
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

void decode_png_samples(const std::string& path, PngSamples& out) {
    const auto scratch = decode_scratch.take();
    read_whole_file(path, scratch->file);
    SpngCtx c;
    const spng_ihdr ihdr = png_header(path, c, scratch->file);
    spng_trns trns{};
    const int has_trns = spng_get_trns(c.ctx, &trns);
    if (has_trns != 0 && has_trns != SPNG_ECHUNKAVAIL) png_fail(path, has_trns);
    const bool grey = ihdr.color_type == SPNG_COLOR_TYPE_GRAYSCALE ||
                      ihdr.color_type == SPNG_COLOR_TYPE_GRAYSCALE_ALPHA;
    const bool alpha = has_trns == 0 || ihdr.color_type == SPNG_COLOR_TYPE_GRAYSCALE_ALPHA ||
                       ihdr.color_type == SPNG_COLOR_TYPE_TRUECOLOR_ALPHA;
    out.channels = grey ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
    out.index = grey ? std::vector<int>{0} : std::vector<int>{0, 1, 2};
    if (alpha) {
        out.channels.push_back("A");
        out.index.push_back(3);
    }
    out.width = int(ihdr.width);
    out.height = int(ihdr.height);
    out.bits = ihdr.bit_depth == 16 ? 16 : 8;
    if (out.bits != 16) {
        out.rgba16.clear();
        return;
    }
    const std::size_t n = std::size_t(out.width) * out.height;
    out.rgba16.resize(n * 4);
    const int err =
        spng_decode_image(c.ctx, out.rgba16.data(), n * 8, SPNG_FMT_RGBA16, SPNG_DECODE_TRNS);
    if (err) png_fail(path, err);
}

bool has_png_signature(const std::string& path) {
    // Regular files only: opening a pipe or a device would wait or read without end (the
    // readers refuse those with their own message).
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;
    std::uint8_t head[8] = {};
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    const std::size_t got = std::fread(head, 1, 8, f);
    std::fclose(f);
    return got == 8 && std::memcmp(head, kPngSignature, 8) == 0;
}

}  // namespace deepsea::io_detail
