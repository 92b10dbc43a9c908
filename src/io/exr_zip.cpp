#include "exr_zip.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <mutex>

#include "byte_simd.h"
#include "codec_files.h"
#include "deepsea/core/error.h"
#include "file_checks.h"

#if DEEPSEA_EXR_OWN_ZIP
namespace deepsea::io_detail {

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
    i = predictor_sums_sse2(in, n);
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
    k = interleave_sse2(lo, hi, half, out);
#endif
    for (; k < half; ++k) {
        out[2 * k] = lo[k];
        out[2 * k + 1] = hi[k];
    }
    if (n % 2) out[n - 1] = lo[half];
}

}  // namespace

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
        exr_call(path, [&] {
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
        });
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

}  // namespace deepsea::io_detail
#endif  // DEEPSEA_EXR_OWN_ZIP
