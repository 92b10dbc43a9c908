#include "deepsea/io/image_io.h"

#include <fcntl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

#include "deepsea/colour/srgb.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/io/depth_formats.h"
#include "fast_codecs.h"
#include "file_checks.h"
#include "oiio_plugin.h"

namespace deepsea {

namespace fs = std::filesystem;

using io_detail::check_exr_header;
using io_detail::check_png_claim;
using io_detail::io_fail;
using io_detail::require_readable;

namespace {

std::string lower(std::string s) {
    for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return s;
}

std::string extension(const std::string& path) { return lower(fs::path(path).extension()); }

std::string join(const std::vector<std::string>& v) {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
    return out;
}

/// Codec libraries (libpng above all) print their own errors and warnings on stderr before
/// OIIO hands the same error back; deepsea reports it once, as its one line. So stderr points
/// to /dev/null while any codec call runs (counted, so concurrent calls in a pipeline share
/// one redirection and the last to finish restores it).
class QuietCodecs {
public:
    QuietCodecs() {
        std::lock_guard<std::mutex> lock(mutex());
        if (count()++ > 0) return;
        std::fflush(stderr);
        saved() = ::dup(2);
        const int null = ::open("/dev/null", O_WRONLY);
        if (null >= 0) {
            ::dup2(null, 2);
            ::close(null);
        }
    }
    ~QuietCodecs() {
        std::lock_guard<std::mutex> lock(mutex());
        if (--count() > 0) return;
        if (saved() >= 0) {
            ::dup2(saved(), 2);
            ::close(saved());
            saved() = -1;
        }
    }
    QuietCodecs(const QuietCodecs&) = delete;
    QuietCodecs& operator=(const QuietCodecs&) = delete;

private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    static int& count() {
        static int n = 0;
        return n;
    }
    static int& saved() {
        static int fd = -1;
        return fd;
    }
};

using io_detail::OiioHeader;
using io_detail::OiioPixel;

/// An image open in OpenImageIO (through the module): its header, checked before any pixel
/// is allocated (a 76-byte PNG can claim 20000x20000), and its reader.
class OiioInput {
public:
    explicit OiioInput(const std::string& path) : m_path(path) {
        require_readable(path);
        check_exr_header(path);
        m_input.plugin = &io_detail::oiio(path);
        std::string error;
        {
            const QuietCodecs quiet;
            m_input.handle = m_input.plugin->open(path, m_header, error);
        }
        if (!m_input.handle) io_fail(path, error);
        check_image_size(m_header.width, m_header.height, m_header.channels, path);
        if (m_header.format_name == "png") {
            std::error_code ec;
            const auto bytes = fs::file_size(path, ec);
            if (!ec) check_png_claim(path, m_header.width, m_header.height, bytes);
        }
        if (m_header.depth > 1)
            io_fail(path, "a volume image (depth " + std::to_string(m_header.depth) + ")");
    }
    OiioInput(const OiioInput&) = delete;
    OiioInput& operator=(const OiioInput&) = delete;

    const OiioHeader& header() const { return m_header; }

    /// Channels [chbegin, chend) of subimage 0 into `out` (pixels x channels values), as float
    /// (integer formats normalised to [0, 1] by OIIO) or as 16-bit codes.
    template <typename T>
    void read(int chbegin, int chend, std::vector<T>& out) {
        static_assert(std::is_same_v<T, float> || std::is_same_v<T, std::uint16_t>);
        out.resize(std::size_t(m_header.width) * m_header.height * (chend - chbegin));
        std::string error;
        const QuietCodecs quiet;
        if (!m_input.plugin->read(m_input.handle, chbegin, chend, std::is_same_v<T, std::uint16_t>,
                                  out.data(), error))
            io_fail(m_path, error);
    }

private:
    /// Closed by its destructor, also when a header check throws from OiioInput's constructor.
    struct Handle {
        const io_detail::OiioPlugin* plugin = nullptr;
        void* handle = nullptr;
        ~Handle() {
            if (handle) plugin->close(handle);
        }
    };
    std::string m_path;
    Handle m_input;
    OiioHeader m_header;
};

bool is_float_format(OiioPixel t) {
    return t == OiioPixel::Float || t == OiioPixel::Half || t == OiioPixel::Double;
}

[[noreturn]] void fail_no_writer(const std::string& path) {
    const std::string ext = fs::path(path).extension().string();
    io_fail(path, (ext.empty() ? std::string("no extension to choose an image format by")
                               : "no image writer for the extension '" + ext + "'") +
                      " (use .png, .jpg, .tif or .exr)");
}

/// Writes `data` (interleaved float, spec.channels per pixel) atomically through OpenImageIO;
/// the temporary keeps the extension, so OIIO picks the same format. IoError names `path`.
void write_image(const std::string& path, const io_detail::OiioWriteSpec& spec,
                 const std::vector<float>& data) {
    const io_detail::OiioPlugin& oiio = io_detail::oiio(path);
    write_atomically(path, [&](const std::string& tmp) {
        std::string error;
        io_detail::OiioWritten w;
        {
            const QuietCodecs quiet;
            w = oiio.write(tmp, spec, data.data(), error);
        }
        if (w == io_detail::OiioWritten::NoWriter) fail_no_writer(path);
        if (w == io_detail::OiioWritten::Failed)
            io_fail(path, error.empty() ? std::string("write failed (disk full?)") : error);
    });
}

/// The channel of a depth file to read: the one named in opt, else the only one, else the
/// one channel named Z, depth or depth.Z. InputError when that leaves no single choice.
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

bool is_linear_extension(const std::string& ext) {
    return ext == ".exr" || ext == ".hdr" || ext == ".pfm";
}

Image read_color_oiio(const std::string& path);
Image read_depth_oiio(const std::string& path, const DepthReadOptions& opt);

/// `img` as width x height x channels, its storage reused when it has the room.
void fit(Image& img, int width, int height, int channels) {
    img.width = width;
    img.height = height;
    img.channels = channels;
    img.data.resize(std::size_t(width) * height * channels);
}

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

}  // namespace

Image read_color(const std::string& path) {
    Image img;
    read_color(path, img);
    return img;
}

void read_color(const std::string& path, Image& out) {
    io_detail::PngRgb& p = t_png;
    if (!read_srgb_codes(path, p)) {
        out = read_color_oiio(path);
        return;
    }
    // The decode table straight from the integer codes.
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

void read_frame_color(const std::string& path, Frame& frame) {
    if (read_srgb_codes(path, frame.codes)) {
        frame.rgb = Image();
        return;
    }
    frame.codes.width = frame.codes.height = 0;
    read_color(path, frame.rgb);
}

namespace {

Image read_color_oiio(const std::string& path) {
    if (extension(path) == ".pfm") {
        Image src = read_pfm(path);
        Image rgb = src;
        if (src.channels != 3) {
            rgb = Image(src.width, src.height, 3);
            for (std::size_t i = 0; i < src.data.size(); ++i)
                for (int c = 0; c < 3; ++c) rgb.data[i * 3 + c] = src.data[i];
        }
        require_finite_color(rgb, path);
        return rgb;
    }
    OiioInput in(path);
    const OiioHeader& spec = in.header();
    // 1 = grey, 2 = grey + alpha; otherwise the first three are R, G, B (alpha dropped). Two
    // channels that are not grey and alpha (an EXR's R and G, or Z and A) are no colour image.
    if (spec.channels == 2 &&
        (spec.channel_names.size() != 2 || lower(spec.channel_names[1]) != "a")) {
        throw InputError(path + ": its 2 channels (" + join(spec.channel_names) +
                         ") are not a colour image: deepsea reads R, G, B (+ A) or grey (+ A)");
    }
    const int use = spec.channels >= 3 ? 3 : 1;
    std::vector<float> buf;
    in.read(0, use, buf);
    const bool encoded = !is_float_format(spec.pixel);
    // 8- and 16-bit files hold one of 2^bits codes: decode through a table of srgb_to_linear.
    const int codes = spec.pixel == OiioPixel::UInt8    ? 255
                      : spec.pixel == OiioPixel::UInt16 ? 65535
                                                        : 0;
    const float* lut = codes ? srgb_decode_table(codes) : nullptr;
    Image img(spec.width, spec.height, 3);
    const std::size_t n = std::size_t(spec.width) * spec.height;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            for (int c = 0; c < 3; ++c) {
                const float v = buf[i * use + (use == 3 ? c : 0)];
                float& out = img.data[i * 3 + c];
                if (!encoded) {
                    out = v;
                } else if (codes) {
                    out = lut[std::size_t(std::lround(std::clamp(v, 0.0f, 1.0f) * codes))];
                } else {
                    out = srgb_to_linear(v);
                }
            }
        }
    });
    if (!encoded) require_finite_color(img, path);
    return img;
}

}  // namespace

Image read_depth(const std::string& path, const DepthReadOptions& opt) {
    Image img;
    read_depth(path, img, opt);
    return img;
}

void read_depth(const std::string& path, Image& out, const DepthReadOptions& opt) {
    const std::string ext = extension(path);
    if (ext == ".exr") {
        io_detail::ExrReader in(path);
        const int ch = depth_channel(path, in.channels(), opt);
        fit(out, in.width(), in.height(), 1);
        in.read(ch, out.data.data());
        // An integer channel (OpenEXR's 32-bit UINT) counts units of --depth-scale, millimetres
        // by default, as a 16-bit PNG does; half and float channels are metres.
        if (!in.is_float(ch))
            for (float& v : out.data) v = float(double(v) * opt.scale);
        return;
    } else if (ext == ".png" && (opt.channel.empty() || opt.channel == "Y")) {
        thread_local std::vector<std::uint16_t> raw;
        int w = 0, h = 0;
        if (io_detail::decode_png_grey16(path, w, h, raw)) {
            fit(out, w, h, 1);
            for (std::size_t i = 0; i < raw.size(); ++i)
                out.data[i] = float(double(raw[i]) * opt.scale);
            return;
        }
    }
    out = read_depth_oiio(path, opt);
}

namespace {

Image read_depth_oiio(const std::string& path, const DepthReadOptions& opt) {
    const std::string ext = extension(path);
    if (ext == ".npy") return read_npy(path, opt.scale);
    if (ext == ".pfm") {
        const Image src = read_pfm(path);
        const int ch = depth_channel(path,
                                     src.channels == 1 ? std::vector<std::string>{"Y"}
                                                       : std::vector<std::string>{"R", "G", "B"},
                                     opt);
        Image img(src.width, src.height, 1);
        for (std::size_t i = 0; i < img.data.size(); ++i)
            img.data[i] = src.data[i * src.channels + ch];
        return img;
    }

    OiioInput in(path);
    const OiioHeader& spec = in.header();
    const int ch = depth_channel(path, spec.channel_names, opt);
    Image img(spec.width, spec.height, 1);
    if (is_float_format(spec.pixel)) {
        in.read(ch, ch + 1, img.data);
    } else if (spec.pixel == OiioPixel::UInt16) {
        std::vector<std::uint16_t> raw;
        in.read(ch, ch + 1, raw);
        for (std::size_t i = 0; i < raw.size(); ++i)
            img.data[i] = float(double(raw[i]) * opt.scale);
    } else {
        throw InputError(path + ": depth must be float or 16-bit integer, not " + spec.pixel_name +
                         " (8 bits cannot hold a useful depth range)");
    }
    return img;
}

}  // namespace

bool has_image_writer(const std::string& path) {
    const std::string ext = extension(path);
    if (ext.empty()) return false;
    // deepsea's own writers: answered without loading OpenImageIO.
    if (writes_encoded(path) || ext == ".exr") return true;
    const QuietCodecs quiet;
    return io_detail::oiio(path).has_writer(path);
}

void require_image_writer(const std::string& path) {
    if (!has_image_writer(path)) fail_no_writer(path);
}

std::string image_format(const std::string& path) {
    const std::string ext = extension(path);
    if (ext == ".jpeg") return "jpg";
    if (ext == ".tiff") return "tif";
    return ext.empty() ? ext : ext.substr(1);
}

bool writes_encoded(const std::string& path) {
    const std::string ext = extension(path);
    return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

void prepare_encoded(int width, int height, int channels, int bits, const std::string& path,
                     EncodedImage& out) {
    out.width = width;
    out.height = height;
    out.channels = channels;
    out.bits = extension(path) == ".png" ? bits : 8;
    const std::size_t n = std::size_t(width) * height * channels;
    if (out.bits == 8) {
        out.codes8.resize(n);
    } else {
        out.codes16.resize(n);
    }
}

void encode_srgb_samples(const float* linear, std::size_t n, double exposure, std::size_t first,
                         EncodedImage& out) {
    if (out.bits == 8) {
        srgb_encode(linear, n, exposure, out.codes8.data() + first);
    } else {
        srgb_encode(linear, n, exposure, out.codes16.data() + first);
    }
}

void encode_srgb(const Image& linear_rgb, double exposure, int bits, const std::string& path,
                 EncodedImage& out) {
    prepare_encoded(linear_rgb.width, linear_rgb.height, linear_rgb.channels, bits, path, out);
    const float* in = linear_rgb.data.data();
    // Isolated, as in read_color: write_color calls this with a thread-local target.
    tbb::this_task_arena::isolate([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, linear_rgb.data.size(), 1 << 16),
                          [&](const auto& r) {
                              encode_srgb_samples(in + r.begin(), r.size(), exposure, r.begin(),
                                                  out);
                          });
    });
}

void write_encoded(const std::string& path, const EncodedImage& img, const ImageMetadata& meta) {
    const std::string ext = extension(path);
    if (ext == ".png") {
        io_detail::write_png(path, img.width, img.height, img.channels,
                             img.bits == 8 ? img.codes8.data() : nullptr,
                             img.bits == 16 ? img.codes16.data() : nullptr, meta);
    } else if ((ext == ".jpg" || ext == ".jpeg") && img.bits == 8) {
        io_detail::write_jpeg(path, img.width, img.height, img.channels, img.codes8.data(), meta);
    } else {
        throw InputError(path + ": write_encoded writes 8/16-bit PNG and 8-bit JPEG only");
    }
}

void write_color(const std::string& path, const Image& linear_rgb, int bits,
                 const ImageMetadata& meta, double exposure) {
    if (linear_rgb.channels != 3 && linear_rgb.channels != 1)
        throw InputError(path + ": write_color needs 1 or 3 channels, got " +
                         std::to_string(linear_rgb.channels));
    if (linear_rgb.empty()) throw InputError(path + ": empty image");
    if (bits != 8 && bits != 16)
        throw InputError(path + ": bit depth must be 8 or 16, got " + std::to_string(bits));
    const std::string ext = extension(path);
    const int nch = linear_rgb.channels;
    const std::size_t n = linear_rgb.data.size();
    // The same float as apply_exposure's: the factor in double, rounded once.
    const auto exposed = [&](std::size_t i) { return float(linear_rgb.data[i] * exposure); };
    if (writes_encoded(path)) {
        thread_local EncodedImage codes;  // kept from frame to frame
        encode_srgb(linear_rgb, exposure, bits, path, codes);
        write_encoded(path, codes, meta);
        return;
    }
    std::vector<float> data(n);
    if (is_linear_extension(ext)) {
        // Float formats keep radiance above 1 (HDR); only non-finite values are cleaned.
        for (std::size_t i = 0; i < data.size(); ++i) {
            const float v = exposed(i);
            data[i] = std::isfinite(v) ? v : 0.0f;
        }
    } else {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, data.size(), 8192),
                          [&](const auto& r) {
                              for (std::size_t i = r.begin(); i < r.end(); ++i) {
                                  float v = exposed(i);
                                  v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
                                  data[i] = linear_to_srgb(v);
                              }
                          });
    }
    const std::vector<std::string> names =
        nch == 3 ? std::vector<std::string>{"R", "G", "B"} : std::vector<std::string>{"Y"};
    if (ext == ".exr") {
        // Through OpenEXR itself, as OpenImageIO wrote them: half, ZIP, the metadata as string
        // attributes.
        std::vector<io_detail::ExrChannel> channels;
        for (int c = 0; c < nch; ++c) channels.push_back({names[c], data.data() + c, nch});
        io_detail::write_exr(path, linear_rgb.width, linear_rgb.height, channels, true, "zip",
                             meta);
        return;
    }
    io_detail::OiioWriteSpec spec;
    spec.width = linear_rgb.width;
    spec.height = linear_rgb.height;
    spec.channels = nch;
    spec.channel_names = names;
    spec.attributes = meta;
    if (is_linear_extension(ext)) {
        spec.pixel = OiioPixel::Float;
        spec.attributes.emplace_back("oiio:ColorSpace", "Linear");
    } else {
        spec.pixel = bits == 16 ? OiioPixel::UInt16 : OiioPixel::UInt8;
        spec.attributes.emplace_back("oiio:ColorSpace", "sRGB");
    }
    write_image(path, spec, data);
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

void write_depth_exr(const std::string& path, const Image& depth) {
    if (depth.channels != 1)
        throw InputError(path + ": a depth map has 1 channel, got " +
                         std::to_string(depth.channels));
    if (depth.empty()) throw InputError(path + ": empty depth map");
    io_detail::write_exr(path, depth.width, depth.height, {{"Z", depth.data.data(), 1}}, false,
                         "zip", {});
}

void write_exr_layers(const std::string& path, const std::vector<ExrLayer>& layers,
                      const ImageMetadata& meta, bool half) {
    if (layers.empty()) throw InputError(path + ": no layers to write");
    int total = 0;
    const Image* first = nullptr;
    for (const auto& l : layers) {
        if (!l.image || l.image->empty())
            throw InputError(path + ": layer '" + l.name + "' has no image");
        if (int(l.channels.size()) != l.image->channels)
            throw InputError(path + ": layer '" + l.name + "' names " +
                             std::to_string(l.channels.size()) + " channels but its image has " +
                             std::to_string(l.image->channels));
        if (!first) first = l.image;
        if (l.image->width != first->width || l.image->height != first->height)
            throw InputError(
                path + ": layer '" + l.name + "' is " + std::to_string(l.image->width) + "x" +
                std::to_string(l.image->height) + ", layer '" + layers[0].name + "' is " +
                std::to_string(first->width) + "x" + std::to_string(first->height));
        total += l.image->channels;
    }
    // Each channel is a slice of its layer's own image: OpenEXR reads them in place (and
    // converts to half itself), nothing is interleaved or copied here. PIZ (lossless wavelet):
    // on 800x800 render layers 1.6x faster to write than ZIP and 20 % smaller.
    std::vector<io_detail::ExrChannel> channels;
    for (const auto& l : layers) {
        const int lc = l.image->channels;
        for (int c = 0; c < lc; ++c) {
            channels.push_back({l.name.empty() ? l.channels[c] : l.name + "." + l.channels[c],
                                l.image->data.data() + c, lc});
        }
    }
    (void)total;
    io_detail::write_exr(path, first->width, first->height, channels, half, "piz", meta);
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
