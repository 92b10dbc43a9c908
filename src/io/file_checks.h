#pragma once
// What io's readers share (private to deepsea_io): one error style and one check that a file
// can be opened, for the OIIO formats in image_io.cpp and the hand-parsed ones in
// depth_formats.cpp.

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "deepsea/core/error.h"

namespace deepsea::io_detail {

/// Throws IoError "path: why" on one line (OIIO's messages span several lines, and a damaged
/// file can make them huge).
[[noreturn]] inline void io_fail(const std::string& path, const std::string& why) {
    const std::string line = one_line(why);
    throw IoError(path + ": " + (line.empty() ? std::string("unknown error") : line));
}

/// Missing files get a plain reason instead of OIIO's "could not find a format reader".
inline void require_readable(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto st = fs::status(path, ec);
    if (ec || !fs::exists(st)) io_fail(path, "no such file");
    if (fs::is_directory(st)) io_fail(path, "is a folder, not an image");
    std::ifstream probe(path, std::ios::binary);
    if (!probe) io_fail(path, std::strerror(errno));
}

}  // namespace deepsea::io_detail
