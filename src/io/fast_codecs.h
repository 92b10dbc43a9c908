#pragma once
// The fast paths of image_io (private to deepsea_io): PNG decoded by libspng or libdeflate
// (png_decode.cpp) and encoded by hand (png_encode.cpp), JPEG through libjpeg-turbo (jpeg.cpp),
// EXR read and written through OpenEXR with its own thread pool (exr.cpp): the formats
// datasets use, without OpenImageIO's per-call overhead and float conversions (docs/runtime.md,
// "Where the time goes"). OpenImageIO stays for every other format. Every function here
// keeps image_io's guards: header sizes checked before allocation, one-line IoErrors naming
// the file, atomic writes.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "deepsea/core/frame.h"
#include "deepsea/io/image_io.h"

namespace deepsea::io_detail {

/// A PNG decoded to interleaved RGB: 8 bits per sample for files of 1 to 8 bits (palette and
/// grey expanded, alpha dropped), 16 bits (host order) for 16-bit files.
using PngRgb = SrgbCodes;

/// Decodes `path` into `out`, reusing its buffers. IoError naming the file for a corrupt or
/// truncated file; InputError (check_image_size) for a header beyond deepsea's limits, before
/// any pixel is allocated.
void decode_png_rgb(const std::string& path, PngRgb& out);

/// If `path` is a 16-bit one-channel PNG, decodes it into `values` (host order, resized) and
/// returns true; returns false, having decoded nothing, for any other PNG. Errors as
/// decode_png_rgb.
bool decode_png_grey16(const std::string& path, int& width, int& height,
                       std::vector<std::uint16_t>& values);

/// A PNG as OpenImageIO presents it to a depth reader: channels named Y, Y A, R G B or
/// R G B A (a palette expanded to RGB, a tRNS chunk read as alpha), 16 bits per sample or 8
/// (files of 1 to 8 bits). For 16-bit files every pixel's samples as RGBA in `rgba16` (host
/// order, grey in R, G and B): channel k of pixel i is rgba16[4 * i + index[k]].
struct PngSamples {
    int width = 0, height = 0, bits = 8;
    std::vector<std::string> channels;
    std::vector<int> index;
    std::vector<std::uint16_t> rgba16;  ///< empty for 8-bit files
};

/// Decodes `path` into `out`, reusing its buffers. Errors as decode_png_rgb.
void decode_png_samples(const std::string& path, PngSamples& out);

/// True if the file starts with PNG's signature, whatever its name (false if it cannot be
/// read): such files are read by libspng, never by OpenImageIO, whose libpng prints its errors
/// on stderr.
bool has_png_signature(const std::string& path);

/// Writes a PNG atomically: `channels` (1 or 3) interleaved samples per pixel, 8 bits
/// (`pixels8`) or 16 bits (`pixels16`, host order); `meta` as tEXt chunks; an sRGB chunk.
/// Rows are filtered with "up"; 8-bit rows are coded as literals and runs (deflate_runs.h),
/// 16-bit ones deflated by ISA-L at level 1 (docs/runtime.md, "Image I/O", has the measurements
/// behind the choice). IoError naming `path`.
void write_png(const std::string& path, int width, int height, int channels,
               const std::uint8_t* pixels8, const std::uint16_t* pixels16,
               const ImageMetadata& meta);

/// Writes a baseline JPEG atomically with OpenImageIO's settings (quality 95, 4:2:0, JFIF),
/// so that the pixels are the same; `meta` goes into one COM marker ("name=value" lines).
void write_jpeg(const std::string& path, int width, int height, int channels,
                const std::uint8_t* pixels, const ImageMetadata& meta);

/// Decodes a JPEG (baseline or progressive, grey or YCbCr) to 8-bit RGB in `rgb` (resized),
/// as libjpeg-turbo decodes it for OpenImageIO. A truncated or damaged file is an IoError
/// naming it (libjpeg's warnings are errors here: it would fill the missing rows with grey).
void decode_jpeg_rgb(const std::string& path, int& width, int& height,
                     std::vector<std::uint8_t>& rgb);

/// One channel of an EXR to write: `base` points at the first pixel's sample, `stride` floats
/// between pixels (rows follow each other).
struct ExrChannel {
    std::string name;
    const float* base = nullptr;
    int stride = 1;
};

/// Writes a scanline EXR atomically through OpenEXR: float or `half` channels, `compression`
/// "zip" or "piz", `meta` as string attributes. IoError naming `path`.
void write_exr(const std::string& path, int width, int height,
               const std::vector<ExrChannel>& channels, bool half, const std::string& compression,
               const ImageMetadata& meta);

/// An EXR opened through OpenEXR (part 0, data window), for reading single channels as float.
class ExrReader {
public:
    /// IoError naming the file if it cannot be opened; InputError if its size is beyond
    /// deepsea's limits.
    explicit ExrReader(const std::string& path);
    ~ExrReader();
    ExrReader(const ExrReader&) = delete;
    ExrReader& operator=(const ExrReader&) = delete;

    int width() const { return m_width; }
    int height() const { return m_height; }
    const std::vector<std::string>& channels() const { return m_channels; }
    /// True if channel `i` is half or float (not uint).
    bool is_float(int i) const { return m_float[i]; }
    /// Reads channel `i` as float into `dst` (width x height values, rows top to bottom).
    void read(int i, float* dst) { read(std::vector<int>{i}, dst); }
    /// Reads the channels `channels` (indices) as float, interleaved in that order, into `dst`.
    void read(const std::vector<int>& channels, float* dst);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    std::string m_path;
    int m_width = 0, m_height = 0;
    std::vector<std::string> m_channels;
    std::vector<bool> m_float;
};

}  // namespace deepsea::io_detail
