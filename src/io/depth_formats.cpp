// Depth formats that OIIO does not read (well): PFM and NumPy .npy, parsed by hand.

#include "deepsea/io/depth_formats.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "deepsea/core/error.h"
#include "file_checks.h"

namespace deepsea {

using io_detail::io_fail;
using io_detail::require_readable;

namespace {

// PFM: parsed by hand so that the row order is ours to get right (PFM stores the bottom row
// first; Image is top to bottom) and the scale sign (byte order) is honoured.

bool read_token(std::istream& is, std::string& tok) {
    tok.clear();
    int ch;
    while ((ch = is.get()) != EOF && std::isspace(ch)) {
    }
    if (ch == EOF) return false;
    tok += char(ch);
    while ((ch = is.peek()) != EOF && !std::isspace(ch)) tok += char(is.get());
    return true;
}

/// IoError unless the stream still holds `need` bytes: these formats are uncompressed, so a
/// header claiming more pixels than the file carries is refused before the raster is allocated
/// (a 40-byte file could otherwise cost hundreds of megabytes first).
void require_bytes(std::istream& is, std::uint64_t need, const std::string& path,
                   const char* what) {
    const auto at = is.tellg();
    is.seekg(0, std::ios::end);
    const auto end = is.tellg();
    is.seekg(at);
    const std::uint64_t have = at >= 0 && end >= at ? std::uint64_t(end - at) : 0;
    if (have < need) {
        io_fail(path, std::string("truncated ") + what + " (the header needs " +
                          std::to_string(need) + " bytes of data, the file holds " +
                          std::to_string(have) + ")");
    }
}

}  // namespace

Image read_pfm(const std::string& path) {
    require_readable(path);
    std::ifstream is(path, std::ios::binary);
    std::string magic, ws, hs, ss;
    if (!read_token(is, magic) || (magic != "Pf" && magic != "PF"))
        io_fail(path, "not a PFM file (bad magic)");
    if (!read_token(is, ws) || !read_token(is, hs) || !read_token(is, ss))
        io_fail(path, "truncated PFM header");
    is.get();  // the single whitespace byte before the raster
    int w = 0, h = 0;
    double scale = 0.0;
    try {
        w = std::stoi(ws);
        h = std::stoi(hs);
        scale = std::stod(ss);
    } catch (const std::exception&) {
        io_fail(path, "bad PFM header");
    }
    if (w <= 0 || h <= 0 || scale == 0.0 || !std::isfinite(scale)) io_fail(path, "bad PFM header");
    const int nch = magic == "PF" ? 3 : 1;
    check_image_size(w, h, nch, path);
    require_bytes(is, std::uint64_t(w) * h * nch * 4, path, "PFM raster");
    Image img(w, h, nch);
    const bool little = scale < 0.0;
    std::vector<unsigned char> row(std::size_t(w) * nch * 4);
    for (int r = 0; r < h; ++r) {
        if (!is.read(reinterpret_cast<char*>(row.data()), std::streamsize(row.size())))
            io_fail(path, "truncated PFM raster");
        float* dst = img.row(h - 1 - r);  // bottom row first in the file
        for (std::size_t i = 0; i < std::size_t(w) * nch; ++i) {
            unsigned char b[4];
            std::memcpy(b, &row[i * 4], 4);
            if (!little) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
            std::uint32_t u = std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 |
                              std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
            std::memcpy(&dst[i], &u, 4);
        }
    }
    return img;
}

namespace {

// .npy (NumPy format versions 1-3), parsed by hand: the header is a Python dict literal.

std::string dict_value(const std::string& header, const std::string& key) {
    const auto k = header.find("'" + key + "'");
    if (k == std::string::npos) return {};
    auto p = header.find(':', k);
    if (p == std::string::npos) return {};
    ++p;
    while (p < header.size() && header[p] == ' ') ++p;
    if (p >= header.size()) return {};
    if (header[p] == '\'') {
        const auto e = header.find('\'', p + 1);
        return e == std::string::npos ? std::string() : header.substr(p + 1, e - p - 1);
    }
    if (header[p] == '(') {
        const auto e = header.find(')', p);
        return e == std::string::npos ? std::string() : header.substr(p + 1, e - p - 1);
    }
    auto e = p;
    while (e < header.size() && header[e] != ',' && header[e] != '}') ++e;
    return header.substr(p, e - p);
}

}  // namespace

Image read_npy(const std::string& path, double scale) {
    require_readable(path);
    std::ifstream is(path, std::ios::binary);
    char magic[8];
    if (!is.read(magic, 8) || std::memcmp(magic, "\x93NUMPY", 6) != 0)
        io_fail(path, "not a .npy file (bad magic)");
    const int major = static_cast<unsigned char>(magic[6]);
    std::uint32_t hlen = 0;
    if (major == 1) {
        unsigned char b[2];
        if (!is.read(reinterpret_cast<char*>(b), 2)) io_fail(path, "truncated .npy header");
        hlen = b[0] | std::uint32_t(b[1]) << 8;
    } else if (major == 2 || major == 3) {
        unsigned char b[4];
        if (!is.read(reinterpret_cast<char*>(b), 4)) io_fail(path, "truncated .npy header");
        hlen =
            b[0] | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
    } else {
        io_fail(path, "unsupported .npy version " + std::to_string(major));
    }
    if (hlen > (1u << 20)) io_fail(path, "implausible .npy header length " + std::to_string(hlen));
    std::string header(hlen, '\0');
    if (!is.read(header.data(), hlen)) io_fail(path, "truncated .npy header");

    const std::string descr = dict_value(header, "descr");
    const std::string fortran = dict_value(header, "fortran_order");
    std::vector<long long> shape;
    {
        std::stringstream ss(dict_value(header, "shape"));
        std::string item;
        while (std::getline(ss, item, ',')) {
            if (item.find_first_not_of(" ") == std::string::npos) continue;
            try {
                shape.push_back(std::stoll(item));
            } catch (const std::exception&) {
                io_fail(path, "bad .npy shape");
            }
        }
    }
    int bytes = 0;
    if (descr == "<f4" || descr == "f4")
        bytes = 4;
    else if (descr == "<f8" || descr == "f8")
        bytes = 8;
    else if (descr == "<u2" || descr == "u2")
        bytes = 2;
    else
        throw InputError(path + ": .npy dtype '" + descr +
                         "' is not supported for depth (use <f4, <f8 or <u2)");
    if (!(shape.size() == 2 || (shape.size() == 3 && shape[2] == 1)) || shape[0] <= 0 ||
        shape[1] <= 0)
        throw InputError(path + ": .npy depth must have shape (H, W) or (H, W, 1)");
    check_image_size(shape[1], shape[0], 1, path);
    const bool col_major = fortran.find("True") != std::string::npos;
    const int h = int(shape[0]), w = int(shape[1]);
    require_bytes(is, std::uint64_t(w) * h * bytes, path, ".npy data");
    std::vector<unsigned char> raw(std::size_t(w) * h * bytes);
    if (!is.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size())))
        io_fail(path, "truncated .npy data");
    Image img(w, h, 1);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = col_major ? std::size_t(x) * h + y : std::size_t(y) * w + x;
            const unsigned char* p = &raw[i * bytes];
            float v = 0.0f;
            // .npy data is little-endian ('<'); assemble bytes to stay host-order independent.
            std::uint64_t u = 0;
            for (int k = bytes - 1; k >= 0; --k) u = (u << 8) | p[k];
            if (bytes == 4) {
                const auto u32 = std::uint32_t(u);
                std::memcpy(&v, &u32, 4);
            } else if (bytes == 8) {
                double d;
                std::memcpy(&d, &u, 8);
                v = float(d);
            } else {
                v = float(double(u) * scale);
            }
            img.at(x, y) = v;
        }
    }
    return img;
}

}  // namespace deepsea
