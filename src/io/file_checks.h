#pragma once
// What io's readers share (private to deepsea_io): one error style and one check that a file
// can be opened, for the OIIO formats in image_oiio.cpp and the hand-parsed ones in
// depth_formats.cpp.

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "deepsea/core/error.h"
#include "deepsea/core/input_file.h"

namespace deepsea::io_detail {

/// Throws IoError "path: why" on one line (OIIO's messages span several lines, and a damaged
/// file can make them huge).
[[noreturn]] inline void io_fail(const std::string& path, const std::string& why) {
    const std::string line = one_line(why);
    throw IoError(path + ": " + (line.empty() ? std::string("unknown error") : line));
}

/// Missing files get a plain reason instead of OIIO's "could not find a format reader".
/// Devices (/dev/zero), pipes and files beyond kMaxImageFileBytes are refused before a codec
/// reads from them.
inline void require_readable(const std::string& path) {
    require_input_file(path, kMaxImageFileBytes, "an image");
}

/// OpenEXR allocates each header attribute at the size the file states before reading it: a
/// 273-byte file whose attribute claims 2.4 GB costs 2.4 GB and seconds before the error. So an
/// EXR header is walked first (magic, version, then name, type, int32 size, value per
/// attribute; an empty name ends a header, and an empty header ends a multi-part file's list)
/// and refused when a size runs past the end of the file. Files that are not EXR pass.
void check_exr_header(const std::string& path);

/// PNG pixels are only ever deflated, and deflate packs at most 1032 bytes into one, so a file
/// holds at least height x ceil(width / 8) raw bytes / 1032 (one bit a pixel, palette images
/// included). Decoders allocate the whole image before they decode a row: a 76-byte PNG
/// claiming 9000x9000 would cost a gigabyte before its error. Refused here first.
void check_png_claim(const std::string& path, long long width, long long height,
                     std::uintmax_t bytes);

}  // namespace deepsea::io_detail
