// libFuzzer target: the image and depth readers (src/io/image_io.cpp: the fast codecs,
// image_oiio.cpp through OpenImageIO, depth_formats.cpp by hand: .npy and PFM). Built twice
// (tests/fuzz/CMakeLists.txt): fuzz_depth calls read_depth, fuzz_image (DEEPSEA_FUZZ_COLOR)
// calls read_color.
//
// The readers take paths and choose the format by extension, so the input is written to a
// scratch file named after its magic bytes; bytes without a known magic go out under an
// extension picked by their first byte, so that foreign data under every name is tried too.
// Any input must give an image within the stated size limits or a deepsea::Error.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "deepsea/core/error.h"
#include "deepsea/core/image.h"
#include "deepsea/io/image_io.h"
#include "fuzz_util.h"

namespace {

bool starts_with(const std::uint8_t* data, std::size_t size, const char* magic, std::size_t n) {
    return size >= n && std::memcmp(data, magic, n) == 0;
}

const char* extension_for(const std::uint8_t* data, std::size_t size) {
    if (starts_with(data, size, "\x93NUMPY", 6)) return ".npy";
    if (starts_with(data, size, "PF", 2) || starts_with(data, size, "Pf", 2)) return ".pfm";
    if (starts_with(data, size, "\x76\x2f\x31\x01", 4)) return ".exr";
    if (starts_with(data, size, "\x89PNG", 4)) return ".png";
    if (starts_with(data, size, "II*\0", 4) || starts_with(data, size, "MM\0*", 4)) return ".tif";
    if (starts_with(data, size, "\xff\xd8", 2)) return ".jpg";
    if (starts_with(data, size, "#?", 2)) return ".hdr";
    static const char* const any[] = {".npy", ".pfm", ".exr", ".png", ".tif", ".jpg", ".hdr"};
    return any[size ? data[0] % (sizeof any / sizeof any[0]) : 0];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path =
        deepsea::fuzz::write_input(std::string("input") + extension_for(data, size), data, size);
    try {
#ifdef DEEPSEA_FUZZ_COLOR
        const deepsea::Image img = deepsea::read_color(path);
        const int want_channels = 3;
#else
        const deepsea::Image img = deepsea::read_depth(path);
        const int want_channels = 1;
#endif
        if (img.channels != want_channels ||
            img.data.size() != std::size_t(img.width) * img.height * img.channels ||
            img.width < 1 || img.height < 1 ||
            (long long)img.width * img.height > deepsea::kMaxImagePixels) {
            std::fprintf(stderr, "reader returned a %dx%dx%d image with %zu values\n", img.width,
                         img.height, img.channels, img.data.size());
            std::abort();
        }
    } catch (const deepsea::Error&) {
    }
    return 0;
}
