#pragma once
// What image_io's files share (private to deepsea_io): image_io.cpp reads and dispatches by
// format, image_write.cpp writes, image_oiio.cpp holds the formats without a fast path
// (OpenImageIO's module, PFM, .npy).

#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/core/image.h"
#include "deepsea/io/image_io.h"
#include "oiio_plugin.h"

namespace deepsea::io_detail {

inline std::string lower(std::string s) {
    for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return s;
}

/// The extension of `path` with its dot, lower case ("" without one).
inline std::string extension(const std::string& path) {
    return lower(std::filesystem::path(path).extension());
}

/// "a, b, c"
inline std::string join(const std::vector<std::string>& v) {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
    return out;
}

/// Formats whose values are linear radiance (no sRGB curve), kept above 1.
inline bool is_linear_extension(const std::string& ext) {
    return ext == ".exr" || ext == ".hdr" || ext == ".pfm";
}

/// `img` as width x height x channels, its storage reused when it has the room.
inline void fit(Image& img, int width, int height, int channels) {
    img.width = width;
    img.height = height;
    img.channels = channels;
    img.data.resize(std::size_t(width) * height * channels);
}

/// The channel of a depth file to read: the one named in opt, else the only one, else the
/// one channel named Z, depth or depth.Z. InputError when that leaves no single choice.
int depth_channel(const std::string& path, const std::vector<std::string>& names,
                  const DepthReadOptions& opt);

/// InputError naming `path`: depth samples of type `pixel_name` (OpenImageIO's name: uint8,
/// ...), which cannot hold a depth.
[[noreturn]] inline void fail_depth_type(const std::string& path, const std::string& pixel_name) {
    throw InputError(path + ": depth must be float or 16-bit integer, not " + pixel_name +
                     " (8 bits cannot hold a useful depth range)");
}

/// A PNG (libspng) as read_color reads it, whatever its name.
void read_png_color(const std::string& path, Image& out);

/// A PNG's depth, whatever its name: a 16-bit grey file straight from its samples, else the
/// channel chosen among those OpenImageIO would name (decode_png_samples) of a 16-bit file.
void read_png_depth(const std::string& path, Image& out, const DepthReadOptions& opt);

/// read_color of the formats without a fast path: PFM, and the others through OpenImageIO.
Image read_color_oiio(const std::string& path);

/// read_depth of the formats without a fast path: .npy, PFM, and the others through
/// OpenImageIO.
Image read_depth_oiio(const std::string& path, const DepthReadOptions& opt);

/// Writes `data` (interleaved float, spec.channels per pixel) atomically through OpenImageIO;
/// the temporary keeps the extension, so OIIO picks the same format. IoError names `path`.
void write_oiio(const std::string& path, const OiioWriteSpec& spec, const std::vector<float>& data);

/// True if OpenImageIO has a writer for the extension of `path` (loads its module).
bool oiio_has_writer(const std::string& path);

/// Throws IoError naming `path`: no image writer for its extension.
[[noreturn]] void fail_no_writer(const std::string& path);

}  // namespace deepsea::io_detail
