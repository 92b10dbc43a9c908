#include "deepsea/io/image_io.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "deepsea/colour/srgb.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "fast_codecs.h"
#include "file_checks.h"
#include "image_files.h"

namespace deepsea {

namespace fs = std::filesystem;

using io_detail::extension;
using io_detail::fit;
using io_detail::io_fail;
using io_detail::join;
using io_detail::lower;

namespace io_detail {

int depth_channel(const std::string& path, const std::vector<std::string>& names,
                  const DepthReadOptions& opt) {
    const int n = int(names.size());
    if (!opt.channel.empty()) {
        for (int i = 0; i < n; ++i)
            if (names[i] == opt.channel) return i;
        throw InputError(path + " has no channel '" + opt.channel + "' (it has " + join(names) +
                         ")");
    }
    if (n == 1) return 0;
    int found = -1, count = 0;
    for (int i = 0; i < n; ++i) {
        const std::string l = lower(names[i]);
        if (l == "z" || l == "depth" || l == "depth.z") found = i, ++count;
    }
    if (count == 1) return found;
    throw InputError(path + " has channels " + join(names) + ": name the depth channel to use");
}

}  // namespace io_detail

namespace {

thread_local io_detail::PngRgb t_png;

/// PNG (libspng) and JPEG (libjpeg-turbo) decoded into `codes`, reusing its buffers: true.
/// False, having read nothing, for any other format.
bool read_srgb_codes(const std::string& path, SrgbCodes& codes) {
    const std::string ext = extension(path);
    if (ext == ".png") {
        io_detail::decode_png_rgb(path, codes);
        return true;
    }
    if (ext == ".jpg" || ext == ".jpeg") {
        io_detail::decode_jpeg_rgb(path, codes.width, codes.height, codes.rgb8);
        codes.bits = 8;
        return true;
    }
    return false;
}

/// `codes` decoded to linear RGB in `out`, through the decode table.
void decode_codes(const SrgbCodes& p, Image& out) {
    fit(out, p.width, p.height, 3);
    const std::size_t n = std::size_t(p.width) * p.height * 3;
    float* linear = out.data.data();
    // Isolated: a thread waiting here must not pick up another frame's task that would reuse
    // this thread's buffers (a sequence runs readers and writers in one arena).
    tbb::this_task_arena::isolate([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const auto& r) {
            if (p.bits == 16) {
                srgb_decode(p.rgb16.data() + r.begin(), r.size(), linear + r.begin());
            } else {
                srgb_decode(p.rgb8.data() + r.begin(), r.size(), linear + r.begin());
            }
        });
    });
}

}  // namespace

namespace io_detail {

void read_png_color(const std::string& path, Image& out) {
    decode_png_rgb(path, t_png);
    decode_codes(t_png, out);
}

void read_png_depth(const std::string& path, Image& out, const DepthReadOptions& opt) {
    if (opt.channel.empty() || opt.channel == "Y") {
        thread_local std::vector<std::uint16_t> raw;
        int w = 0, h = 0;
        if (decode_png_grey16(path, w, h, raw)) {
            fit(out, w, h, 1);
            for (std::size_t i = 0; i < raw.size(); ++i)
                out.data[i] = float(double(raw[i]) * opt.scale);
            return;
        }
    }
    PngSamples png;
    decode_png_samples(path, png);
    const int ch = depth_channel(path, png.channels, opt);
    if (png.bits != 16) fail_depth_type(path, "uint8");
    fit(out, png.width, png.height, 1);
    const std::uint16_t* samples = png.rgba16.data() + png.index[ch];
    for (std::size_t i = 0; i < out.data.size(); ++i)
        out.data[i] = float(double(samples[4 * i]) * opt.scale);
}

}  // namespace io_detail

Image read_color(const std::string& path) {
    Image img;
    read_color(path, img);
    return img;
}

void read_color(const std::string& path, Image& out) {
    io_detail::PngRgb& p = t_png;
    if (!read_srgb_codes(path, p)) {
        out = io_detail::read_color_oiio(path);
        return;
    }
    // The decode table straight from the integer codes.
    decode_codes(p, out);
}

void read_frame_color(const std::string& path, Frame& frame) {
    if (read_srgb_codes(path, frame.codes)) {
        frame.rgb = Image();
        return;
    }
    frame.codes.width = frame.codes.height = 0;
    read_color(path, frame.rgb);
}

Image read_depth(const std::string& path, const DepthReadOptions& opt) {
    Image img;
    read_depth(path, img, opt);
    return img;
}

void read_depth(const std::string& path, Image& out, const DepthReadOptions& opt) {
    const std::string ext = extension(path);
    if (ext == ".png") {
        io_detail::read_png_depth(path, out, opt);
        return;
    }
    if (ext == ".exr") {
        io_detail::ExrReader in(path);
        const int ch = io_detail::depth_channel(path, in.channels(), opt);
        fit(out, in.width(), in.height(), 1);
        in.read(ch, out.data.data());
        // An integer channel (OpenEXR's 32-bit UINT) counts units of --depth-scale, millimetres
        // by default, as a 16-bit PNG does; half and float channels are metres.
        if (!in.is_float(ch))
            for (float& v : out.data) v = float(double(v) * opt.scale);
        return;
    }
    out = io_detail::read_depth_oiio(path, opt);
}

bool has_image_writer(const std::string& path) {
    const std::string ext = extension(path);
    if (ext.empty()) return false;
    // deepsea's own writers: answered without loading OpenImageIO.
    if (writes_encoded(path) || ext == ".exr") return true;
    return io_detail::oiio_has_writer(path);
}

void require_image_writer(const std::string& path) {
    if (!has_image_writer(path)) io_detail::fail_no_writer(path);
}

std::string image_format(const std::string& path) {
    const std::string ext = extension(path);
    if (ext == ".jpeg") return "jpg";
    if (ext == ".tiff") return "tif";
    return ext.empty() ? ext : ext.substr(1);
}

void require_writable_image(const std::string& path, bool exr_only) {
    const std::string ext = extension(path);
    static const char* known[] = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".exr", ".hdr"};
    const bool ok = exr_only
                        ? ext == ".exr"
                        : std::find(std::begin(known), std::end(known), ext) != std::end(known);
    if (!ok) {
        io_fail(path, ext.empty() ? std::string("no file extension to choose the format by")
                                  : "cannot write '" + ext + "' files (use " +
                                        (exr_only ? ".exr" : ".png, .jpg, .tif or .exr") + ")");
    }
    std::error_code ec;
    if (fs::is_directory(path, ec)) io_fail(path, "is a folder");
    require_writable_folder(path);
}

Image read_exr_layer(const std::string& path, const std::string& layer,
                     const std::vector<std::string>& channels) {
    io_detail::ExrReader in(path);
    const auto& names = in.channels();
    std::vector<int> idx;
    for (const auto& c : channels) {
        const std::string want = layer.empty() ? c : layer + "." + c;
        const auto it = std::find(names.begin(), names.end(), want);
        if (it == names.end())
            throw InputError(path + " has no channel '" + want + "' (it has " + join(names) + ")");
        idx.push_back(int(it - names.begin()));
    }
    const int nc = int(channels.size());
    Image img(in.width(), in.height(), nc);
    in.read(idx, img.data.data());
    return img;
}

}  // namespace deepsea
