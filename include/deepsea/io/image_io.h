#pragma once
/// \file Reading and writing images through OpenImageIO (PFM and .npy depth: depth_formats.h).
/// Every writer goes through core's write_atomically, so no half-written image is ever left
/// behind.

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "deepsea/colour/srgb.h"  // the sRGB curve and codes these readers and writers apply
#include "deepsea/core/frame.h"
#include "deepsea/core/image.h"

namespace deepsea {

/// Colour image as linear RGB float, 3 channels. 8- and 16-bit files are sRGB-decoded;
/// float files (EXR, ...) are taken as linear. Grey is expanded to RGB, alpha dropped.
/// Throws IoError for a missing or unreadable file.
Image read_color(const std::string& path);

/// read_color into `out`, reusing its storage when it has the room (a sequence's frames).
/// PNG is decoded by libspng, other formats by OpenImageIO.
void read_color(const std::string& path, Image& out);

/// The colour of a frame, reusing its buffers: PNG and JPEG as their sRGB codes
/// (frame.codes; frame.rgb emptied), which the compositor decodes a row at a time with the
/// tables read_color uses, so the pixels are the same; other formats as read_color
/// (frame.rgb; frame.codes emptied).
void read_frame_color(const std::string& path, Frame& frame);

/// How to read a depth file.
struct DepthReadOptions {
    std::string channel;   ///< channel name to use; empty: the only channel, or else the one
                           ///< channel named Z, depth or depth.Z (case-insensitive)
    double scale = 0.001;  ///< metres per unit for integer images (ROS 16UC1, EXR UINT)
};

/// One-channel depth in metres from EXR/TIFF float (any single channel: Z, Y, R, depth, or
/// `channel`), 16-bit PNG and 32-bit unsigned EXR channels (integer units times scale), PFM or
/// .npy (float32/float64, 2-D).
/// Values are copied as they are; non-finite or <= 0 means open water.
/// Throws InputError for a file with several candidate channels and none chosen (the message
/// lists them), for a chosen channel that is absent, and for 8-bit images; IoError for a
/// missing or corrupt file. PFM rows are flipped to top-to-bottom (PFM stores the bottom row
/// first). .npy: dtype <f4, <f8 or <u2 (times scale), shape (H, W) or (H, W, 1).
Image read_depth(const std::string& path, const DepthReadOptions& opt = {});

/// read_depth into `out`, reusing its storage. EXR (half or float channels) is read through
/// OpenEXR, 16-bit grey PNG through libspng, other formats through OpenImageIO.
void read_depth(const std::string& path, Image& out, const DepthReadOptions& opt = {});

/// Text attributes stored with an image: PNG text chunks, EXR header string attributes
/// (name, value), e.g. {"deepsea:exposure", "1.25"}.
using ImageMetadata = std::vector<std::pair<std::string, std::string>>;

/// False if `path` is a PNG without its closing IEND chunk or a JPEG without its end-of-image
/// marker (a file cut short: decoders may still read every row of it), or cannot be read; true
/// for any other file (other formats' decoders notice a short file themselves).
bool image_file_ends(const std::string& path);

/// True if OpenImageIO can write an image with the extension of `path`.
bool has_image_writer(const std::string& path);

/// Throws IoError naming `path` unless has_image_writer: the check a command makes before any
/// work.
void require_image_writer(const std::string& path);

/// The format of `path` by its extension, case-insensitive, with one name per format: "png",
/// "jpg" (.jpg, .jpeg), "tif" (.tif, .tiff), or the extension itself without the dot ("exr",
/// ...; empty without one).
std::string image_format(const std::string& path);

/// Writes linear RGB times `exposure` (as apply_exposure, without its copy): PNG/JPEG/TIFF are
/// sRGB-encoded at `bits` (8 or 16; JPEG is always 8); EXR and other float formats keep linear
/// values (half float). Values are clamped to [0, 1] before encoding. `meta` goes into the
/// file's header (PNG tEXt chunks, a JPEG COM marker of name=value lines, EXR/TIFF
/// attributes). Atomic (temporary file + rename). PNG is encoded by hand with libdeflate,
/// JPEG by libjpeg-turbo, other formats by OpenImageIO. Throws IoError.
void write_color(const std::string& path, const Image& linear_rgb, int bits = 8,
                 const ImageMetadata& meta = {}, double exposure = 1.0);

/// An exposed image as sRGB integer codes, what PNG and JPEG files hold: 8 bits per sample in
/// codes8 or 16 in codes16 (interleaved, 1 or 3 channels). A sequence keeps this (a quarter of
/// the float image at 8 bits) between compositing and writing.
struct EncodedImage {
    int width = 0, height = 0, channels = 0;
    int bits = 8;
    std::vector<std::uint8_t> codes8;
    std::vector<std::uint16_t> codes16;
};

/// True for the formats write_encoded writes (.png, .jpg, .jpeg), whose pixels write_color
/// makes through encode_srgb and write_encoded.
bool writes_encoded(const std::string& path);

/// The codes write_color stores for `linear_rgb` x `exposure` in the format of `path` (PNG:
/// `bits`, JPEG: 8), into `out`, its storage reused.
void encode_srgb(const Image& linear_rgb, double exposure, int bits, const std::string& path,
                 EncodedImage& out);

/// encode_srgb a part at a time: prepare_encoded sizes `out` for width x height x channels in
/// the format of `path` (PNG: `bits`, JPEG: 8), its storage reused; encode_srgb_samples then
/// writes the codes (srgb_encode) of n linear samples times `exposure` from sample `first` on.
/// Parts may be encoded from several threads at once. encode_srgb is these two over the whole
/// image.
void prepare_encoded(int width, int height, int channels, int bits, const std::string& path,
                     EncodedImage& out);
void encode_srgb_samples(const float* linear, std::size_t n, double exposure, std::size_t first,
                         EncodedImage& out);

/// Writes encode_srgb's codes as `path` (PNG or JPEG), with `meta`, atomically. Throws IoError.
void write_encoded(const std::string& path, const EncodedImage& img,
                   const ImageMetadata& meta = {});

/// A camera's display values (camera/camera_stage.h, CameraOutput::image: already through its
/// output curve, in [0, 1]) as integer codes round(v (2^bits - 1)) in the format of `path`
/// (PNG: `bits`, JPEG: 8), with no further curve; v is clamped to [0, 1], NaN to 0.
void encode_display(const Image& display, int bits, const std::string& path, EncodedImage& out);
/// Writes display values as encode_display's codes (PNG, JPEG), 8- or 16-bit TIFF codes, or
/// the values themselves, clamped to [0, 1], in float formats (EXR: half): no exposure, no
/// sRGB curve. `meta` and atomicity as write_color. Throws IoError.
void write_display(const std::string& path, const Image& display, int bits = 8,
                   const ImageMetadata& meta = {});

/// Throws IoError naming `path` unless an image can be written there: an extension deepsea
/// writes (`exr_only`: .exr, for layers; else .png, .jpg, .jpeg, .tif, .tiff, .exr, .hdr), an
/// existing writable folder, not a folder itself. Call it before the work, not after.
void require_writable_image(const std::string& path, bool exr_only = false);

/// Writes a one-channel depth map as a float EXR with channel "Z". Atomic.
void write_depth_exr(const std::string& path, const Image& depth);

/// One layer of a multi-layer EXR: channels named `name.<channel>`.
struct ExrLayer {
    std::string name;                   ///< e.g. "final"; empty: channels named `<channel>`
    const Image* image = nullptr;       ///< must all have the same size
    std::vector<std::string> channels;  ///< e.g. {"R", "G", "B"}, one per image channel
};

/// Writes an EXR with all `layers` (channels "final.R", ..., "depth.Z"), float or `half`,
/// PIZ-compressed, through OpenEXR (its own thread pool). `meta` goes into the header as string
/// attributes. Atomic. Throws IoError.
void write_exr_layers(const std::string& path, const std::vector<ExrLayer>& layers,
                      const ImageMetadata& meta = {}, bool half = false);

/// Reads one layer of a multi-layer EXR written by write_exr_layers (for tests and tools);
/// an empty `layer` reads channels by their plain names. Throws InputError for a missing
/// channel, IoError for an unreadable file.
Image read_exr_layer(const std::string& path, const std::string& layer,
                     const std::vector<std::string>& channels);

}  // namespace deepsea
