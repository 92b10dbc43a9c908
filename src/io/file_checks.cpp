#include "file_checks.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace deepsea::io_detail {

// Both checks run before any decoder (OpenImageIO's or the fast paths') allocates.

void check_exr_header(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char head[8];
    if (!in.read(head, 8) || std::memcmp(head, "\x76\x2f\x31\x01", 4) != 0) return;  // not EXR
    in.seekg(0, std::ios::end);
    const std::streamoff end = in.tellg();
    in.seekg(8);
    const bool multipart = (static_cast<unsigned char>(head[5]) & 0x10) != 0;  // bit 12
    // A null-terminated name of at most 255 characters; empty at the end of a header.
    auto read_name = [&](std::string& name) {
        name.clear();
        for (char ch; in.get(ch);) {
            if (ch == '\0') return true;
            if (name.size() >= 255) return false;
            name += ch;
        }
        return false;
    };
    std::string name, type;
    for (;;) {  // headers: one, or one per part and an empty one after them
        bool empty_header = true;
        for (;;) {  // attributes
            if (!read_name(name)) io_fail(path, "damaged EXR header (an attribute name runs on)");
            if (name.empty()) break;
            empty_header = false;
            unsigned char b[4];
            if (!read_name(type) || !in.read(reinterpret_cast<char*>(b), 4))
                io_fail(path, "damaged EXR header (attribute '" + name + "' is cut short)");
            const std::int64_t size =
                std::int32_t(std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 |
                             std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24);
            const std::int64_t left = end - in.tellg();
            if (size < 0 || size > left) {
                io_fail(path, "damaged EXR header (attribute '" + name + "' claims " +
                                  std::to_string(size) + " bytes, the file holds " +
                                  std::to_string(left) + " after it)");
            }
            in.seekg(size, std::ios::cur);
        }
        if (!multipart || empty_header) return;
    }
}

void check_png_claim(const std::string& path, long long width, long long height,
                     std::uintmax_t bytes) {
    const double least = double(height) * std::ceil(double(width) / 8.0) / 1100.0;
    if (double(bytes) < least) {
        io_fail(path, "its header claims " + std::to_string(width) + "x" + std::to_string(height) +
                          " pixels, more than its " + std::to_string(bytes) +
                          " bytes can hold (truncated or damaged)");
    }
}

}  // namespace deepsea::io_detail

namespace deepsea {

bool image_file_ends(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    // PNG's last chunk is IEND: length 0, its type and its fixed CRC. JPEG ends with EOI.
    static const char kIend[] = "\0\0\0\0IEND\xAE\x42\x60\x82";
    static const char kEoi[] = "\xFF\xD9";
    const bool png = ext == ".png", jpeg = ext == ".jpg" || ext == ".jpeg";
    if (!png && !jpeg) return true;
    const std::size_t n = png ? sizeof kIend - 1 : sizeof kEoi - 1;
    std::ifstream in(path, std::ios::binary);
    char tail[12];
    if (!in.seekg(-std::streamoff(n), std::ios::end) || !in.read(tail, std::streamsize(n)))
        return false;
    return std::memcmp(tail, png ? kIend : kEoi, n) == 0;
}

}  // namespace deepsea
