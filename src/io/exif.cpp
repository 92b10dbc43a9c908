#include "exif.h"

#include <cstring>

namespace deepsea::io_detail {

namespace {

/// A TIFF structure inside the APP1 segment: little- ("II") or big-endian ("MM") numbers.
struct Tiff {
    const std::uint8_t* p;
    std::size_t n;
    bool little;
    bool has(std::size_t at, std::size_t len) const { return at <= n && len <= n - at; }
    unsigned u16(std::size_t at) const {
        return little ? unsigned(p[at]) | unsigned(p[at + 1]) << 8
                      : unsigned(p[at]) << 8 | unsigned(p[at + 1]);
    }
    std::uint32_t u32(std::size_t at) const {
        return little ? std::uint32_t(u16(at)) | std::uint32_t(u16(at + 2)) << 16
                      : std::uint32_t(u16(at)) << 16 | std::uint32_t(u16(at + 2));
    }
};

/// The orientation tag (0x0112, a SHORT) of IFD0, or 1.
int tiff_orientation(const std::uint8_t* p, std::size_t n) {
    if (n < 8 || !(std::memcmp(p, "II", 2) == 0 || std::memcmp(p, "MM", 2) == 0)) return 1;
    const Tiff t{p, n, p[0] == 'I'};
    if (t.u16(2) != 42) return 1;
    const std::size_t ifd = t.u32(4);
    if (!t.has(ifd, 2)) return 1;
    const unsigned entries = t.u16(ifd);
    for (unsigned i = 0; i < entries; ++i) {
        const std::size_t e = ifd + 2 + 12 * std::size_t(i);
        if (!t.has(e, 12)) return 1;
        if (t.u16(e) == 0x0112 && t.u16(e + 2) == 3) {  // type 3: SHORT, value in place
            const unsigned v = t.u16(e + 8);
            return v >= 1 && v <= 8 ? int(v) : 1;
        }
    }
    return 1;
}

}  // namespace

int jpeg_orientation(const std::uint8_t* data, std::size_t size) {
    if (size < 4 || data[0] != 0xFF || data[1] != 0xD8) return 1;
    std::size_t at = 2;
    // Marker segments up to the image data: FF, a marker byte, a 16-bit big-endian length
    // that counts itself.
    while (at + 4 <= size && data[at] == 0xFF) {
        const unsigned marker = data[at + 1];
        if (marker == 0xDA || marker == 0xD9) break;  // start of scan, end of image
        const std::size_t len = std::size_t(data[at + 2]) << 8 | data[at + 3];
        if (len < 2 || at + 2 + len > size) break;
        const std::uint8_t* seg = data + at + 4;
        const std::size_t seg_len = len - 2;
        if (marker == 0xE1 && seg_len >= 6 && std::memcmp(seg, "Exif\0\0", 6) == 0)
            return tiff_orientation(seg + 6, seg_len - 6);
        at += 2 + len;
    }
    return 1;
}

std::string describe_orientation(int orientation) {
    switch (orientation) {
        case 2:
            return "mirrored left-right";
        case 3:
            return "rotated 180 degrees";
        case 4:
            return "mirrored top-bottom";
        case 5:
            return "mirrored along the main diagonal";
        case 6:
            return "rotated 90 degrees clockwise";
        case 7:
            return "mirrored along the other diagonal";
        case 8:
            return "rotated 90 degrees counter-clockwise";
        default:
            return "upright";
    }
}

}  // namespace deepsea::io_detail
