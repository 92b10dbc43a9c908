#pragma once
// OpenImageIO behind a plugin (private to deepsea_io). Debian's OpenImageIO loads about 230
// shared libraries (GDAL, Poppler, FFmpeg, DCMTK, ...): linked into the program they cost every
// process 0.2 s of start-up and 90 MB of resident memory, though PNG, JPEG and EXR never reach
// them (fast_codecs.h). So OpenImageIO is linked into a module, libdeepsea_oiio.so, that
// image_oiio.cpp loads the first time a file needs it (TIFF, HDR, ...). The module holds no
// deepsea code and throws nothing: its functions report failure with a message that
// image_oiio.cpp turns into the usual one-line IoError.

#include <string>
#include <utility>
#include <vector>

namespace deepsea::io_detail {

/// Bumped whenever the structs or the function table below change: a module built from other
/// sources is refused, whatever its file name.
constexpr int kOiioPluginAbi = 1;

enum class OiioPixel { UInt8, UInt16, Half, Float, Double, Other };

/// What an image file's header says.
struct OiioHeader {
    int width = 0, height = 0, channels = 0, depth = 1;
    OiioPixel pixel = OiioPixel::Other;
    std::string pixel_name;   ///< OpenImageIO's name of the stored type, for messages
    std::string format_name;  ///< the reader's format: "png", "tiff", "openexr", ...
    std::vector<std::string> channel_names;
};

/// An image to write: `data` holds `channels` interleaved floats per pixel, stored as `pixel`
/// (OpenImageIO converts, with its own rounding).
struct OiioWriteSpec {
    int width = 0, height = 0, channels = 0;
    OiioPixel pixel = OiioPixel::Float;
    std::vector<std::string> channel_names;  ///< empty: OpenImageIO's defaults
    std::vector<std::pair<std::string, std::string>> attributes;
};

enum class OiioWritten { Written, NoWriter, Failed };

/// The module's functions. Errors come back in `error` (OpenImageIO's own words), never as
/// exceptions.
struct OiioPlugin {
    int abi = kOiioPluginAbi;
    /// Opens `path` (colour left unassociated: alpha is dropped, not composited) and reads its
    /// header; nullptr on failure.
    void* (*open)(const std::string& path, OiioHeader& header, std::string& error);
    /// Channels [begin, end) of subimage 0 into `out`, as float (integer formats scaled to
    /// [0, 1]) or, with `as_uint16`, as 16-bit codes.
    bool (*read)(void* input, int begin, int end, bool as_uint16, void* out, std::string& error);
    void (*close)(void* input);
    /// True if OpenImageIO has a writer for the extension of `path`.
    bool (*has_writer)(const std::string& path);
    /// Writes `path` (the extension picks the format); `error` also names errno's reason.
    OiioWritten (*write)(const std::string& path, const OiioWriteSpec& spec, const float* data,
                         std::string& error);
};

/// The loaded module's table. The first call loads it (DEEPSEA_OIIO_PLUGIN, else next to the
/// program as installed, else where the build put it); IoError naming `path` and every place
/// tried if it cannot be loaded.
const OiioPlugin& oiio(const std::string& path);

}  // namespace deepsea::io_detail

/// The module's one exported symbol.
extern "C" const deepsea::io_detail::OiioPlugin* deepsea_oiio_plugin();
