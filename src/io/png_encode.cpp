// PNG encoding: rows filtered "up", then 8-bit images coded as literals and runs
// (deflate_runs.h) and 16-bit ones deflated by ISA-L's igzip at level 1 (libisal-dev); the CRCs
// are libdeflate's. docs/runtime.md, "Image I/O", has the measurements behind the choices.

#include <isa-l.h>
#include <libdeflate.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <utility>

#include "codec_files.h"
#include "deepsea/core/atomic_file.h"
#include "deflate_runs.h"
#include "fast_codecs.h"
#include "file_checks.h"

namespace deepsea::io_detail {

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

/// igzip level 1's hash tables, one per thread (the stream state lives on the stack).
struct LevelBuffer {
    std::vector<std::uint8_t> b = std::vector<std::uint8_t>(ISAL_DEF_LVL1_DEFAULT);
};

/// The zlib stream of `in` into `out` (which holds at least deflate_bound(size) bytes); its
/// size, or 0 where igzip fails.
std::size_t deflate_zlib(const std::uint8_t* in, std::size_t size, std::uint8_t* out,
                         std::size_t capacity) {
    static thread_local LevelBuffer level;
    isal_zstream s;
    isal_deflate_stateless_init(&s);
    s.level = 1;
    s.level_buf = level.b.data();
    s.level_buf_size = std::uint32_t(level.b.size());
    s.gzip_flag = IGZIP_ZLIB;
    s.end_of_stream = 1;
    s.flush = NO_FLUSH;
    s.next_in = const_cast<std::uint8_t*>(in);
    s.avail_in = std::uint32_t(size);
    s.next_out = out;
    s.avail_out = std::uint32_t(capacity);
    return isal_deflate_stateless(&s) == COMP_OK ? s.total_out : 0;
}

/// Room enough for any stream deflate_zlib makes of `size` bytes: igzip falls back to stored
/// blocks (5 bytes a 64 KiB block) where compressing would expand the data.
std::size_t deflate_bound(std::size_t size) { return size + size / 8 + 1024; }

/// Bytes that are written before they are read: grown without zeroing (a vector's resize
/// would clear megabytes a frame).
struct Bytes {
    std::unique_ptr<std::uint8_t[]> data;
    std::size_t capacity = 0;
    std::uint8_t* at_least(std::size_t n) {
        if (n > capacity) {
            data.reset(new std::uint8_t[n]);
            capacity = n;
        }
        return data.get();
    }
};

/// write_png's scratch: the filtered rows, the chunks before the image data, the file.
struct EncodeScratch {
    Bytes filtered, file;
    std::vector<std::uint8_t> head;
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
    const std::size_t filtered_size = (row + 1) * std::size_t(height);
    std::uint8_t* const f = scratch->filtered.at_least(filtered_size);
    if (pixels16) {
        std::vector<std::uint8_t> prev(row, 0), cur(row);
        for (int y = 0; y < height; ++y) {
            const std::uint16_t* s = pixels16 + std::size_t(y) * width * channels;
            for (std::size_t i = 0; i < row / 2; ++i) {
                cur[2 * i] = std::uint8_t(s[i] >> 8);  // PNG samples are big-endian
                cur[2 * i + 1] = std::uint8_t(s[i]);
            }
            std::uint8_t* d = f + std::size_t(y) * (row + 1);
            d[0] = 2;  // up
            for (std::size_t i = 0; i < row; ++i) d[1 + i] = std::uint8_t(cur[i] - prev[i]);
            std::swap(prev, cur);
        }
    } else {
        for (int y = 0; y < height; ++y) {
            const std::uint8_t* s = pixels8 + std::size_t(y) * row;
            std::uint8_t* d = f + std::size_t(y) * (row + 1);
            d[0] = 2;  // up
            if (y == 0) {
                std::memcpy(d + 1, s, row);
            } else {
                const std::uint8_t* up = s - row;  // the row above
                for (std::size_t i = 0; i < row; ++i) d[1 + i] = std::uint8_t(s[i] - up[i]);
            }
        }
    }
    if (filtered_size > 0x7fffffffu) io_fail(path, "image too large for one PNG stream");
    std::vector<std::uint8_t>& head = scratch->head;
    head.clear();
    head.insert(head.end(), kPngSignature, kPngSignature + 8);
    std::vector<std::uint8_t> ihdr;
    put32(ihdr, std::uint32_t(width));
    put32(ihdr, std::uint32_t(height));
    ihdr.push_back(std::uint8_t(bytes * 8));
    ihdr.push_back(channels == 3 ? 2 : 0);  // truecolour or grey
    ihdr.push_back(0);                      // deflate
    ihdr.push_back(0);                      // adaptive filtering
    ihdr.push_back(0);                      // not interlaced
    chunk(head, "IHDR", ihdr.data(), ihdr.size());
    const std::uint8_t intent = 0;  // sRGB, perceptual
    chunk(head, "sRGB", &intent, 1);
    for (const auto& [name, value] : meta) {
        std::vector<std::uint8_t> text(name.begin(),
                                       name.begin() + std::min<std::size_t>(79, name.size()));
        text.push_back(0);
        text.insert(text.end(), value.begin(), value.end());
        chunk(head, "tEXt", text.data(), text.size());
    }
    // One IDAT chunk holds the whole stream, compressed in place after the chunks before it
    // (no copy of the data). On 8-bit rows a search for matches finds little that runs do not
    // (deflate_runs.h).
    const std::size_t bound =
        pixels16 ? deflate_bound(filtered_size) : deflate_runs_bound(filtered_size);
    const std::size_t at = head.size();
    std::uint8_t* const png = scratch->file.at_least(at + 8 + bound + 4 + 12);
    std::memcpy(png, head.data(), at);
    std::uint8_t* h = png + at;
    const std::size_t z = pixels16 ? deflate_zlib(f, filtered_size, h + 8, bound)
                                   : deflate_runs(f, filtered_size, h + 8);
    if (z == 0 || z > 0x7fffffff) io_fail(path, "deflate failed");
    const auto be32 = [](std::uint8_t* d, std::uint32_t x) {
        d[0] = std::uint8_t(x >> 24), d[1] = std::uint8_t(x >> 16), d[2] = std::uint8_t(x >> 8),
        d[3] = std::uint8_t(x);
    };
    be32(h, std::uint32_t(z));
    std::memcpy(h + 4, "IDAT", 4);
    be32(h + 8 + z, libdeflate_crc32(0, h + 4, z + 4));
    std::uint8_t* iend = h + 8 + z + 4;  // IEND: no data, its CRC
    be32(iend, 0);
    std::memcpy(iend + 4, "IEND", 4);
    be32(iend + 8, libdeflate_crc32(0, iend + 4, 4));
    const std::size_t size = std::size_t(iend + 12 - png);
    write_atomically(path, [&](const std::string& tmp) { write_bytes(tmp, png, size, path); });
}

}  // namespace deepsea::io_detail
