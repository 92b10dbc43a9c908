#pragma once
// What the fast codecs (fast_codecs.h) share, private to deepsea_io: whole files in and out,
// the decoders' scratch buffers and libdeflate's decompressor.

#include <libdeflate.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "buffer_pool.h"
#include "deepsea/core/error.h"
#include "file_checks.h"

namespace deepsea::io_detail {

/// The eight bytes every PNG file starts with.
inline constexpr std::uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

/// The whole file into `bytes` (its capacity reused from frame to frame).
void read_whole_file(const std::string& path, std::vector<std::uint8_t>& bytes);

/// Creates or truncates `file` and writes all of `bytes`, checking every write and the close
/// (a full disk is an IoError naming `name`). No fsync: as OpenImageIO's writers, which the
/// rename after it makes atomic, not durable.
void write_bytes(const std::string& file, const std::uint8_t* bytes, std::size_t size,
                 const std::string& name);

/// A decoder's scratch: the encoded file, and for PNGs the joined IDAT data, the inflated
/// stream of a 16-bit file and its unfiltered rows.
struct DecodeScratch {
    std::vector<std::uint8_t> file, idat, inflated, rows16;
};
/// The PNG and JPEG decoders' scratch.
extern BufferPool<DecodeScratch> decode_scratch;

/// Runs `f`, calls into OpenEXR: the exceptions OpenEXR throws for a file become one IoError
/// naming `path` (deepsea's own errors, and running out of memory, which is no fault of the
/// file, pass through).
template <class F>
void exr_call(const std::string& path, F&& f) {
    try {
        f();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        io_fail(path, e.what());
    }
}

struct Decompressor {
    libdeflate_decompressor* d = libdeflate_alloc_decompressor();
    ~Decompressor() { libdeflate_free_decompressor(d); }
};

}  // namespace deepsea::io_detail
