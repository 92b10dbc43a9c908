// The image formats without a fast path (fast_codecs.h): PFM and .npy by hand
// (depth_formats.h), the others through OpenImageIO's module (oiio_plugin.h).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <type_traits>
#include <vector>

#include "deepsea/colour/srgb.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/io/depth_formats.h"
#include "fast_codecs.h"
#include "file_checks.h"
#include "image_files.h"
#include "oiio_plugin.h"

namespace deepsea::io_detail {

namespace fs = std::filesystem;

namespace {

/// An image open in OpenImageIO (through the module): its header, checked before any pixel
/// is allocated (a 76-byte PNG can claim 20000x20000), and its reader.
class OiioInput {
public:
    explicit OiioInput(const std::string& path) : m_path(path) {
        require_readable(path);
        check_exr_header(path);
        m_input.plugin = &io_detail::oiio(path);
        std::string error;
        m_input.handle = m_input.plugin->open(path, m_header, error);
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

}  // namespace

[[noreturn]] void fail_no_writer(const std::string& path) {
    const std::string ext = fs::path(path).extension().string();
    io_fail(path, (ext.empty() ? std::string("no extension to choose an image format by")
                               : "no image writer for the extension '" + ext + "'") +
                      " (use .png, .jpg, .tif or .exr)");
}

void write_oiio(const std::string& path, const OiioWriteSpec& spec,
                const std::vector<float>& data) {
    const io_detail::OiioPlugin& oiio = io_detail::oiio(path);
    write_atomically(path, [&](const std::string& tmp) {
        std::string error;
        const io_detail::OiioWritten w = oiio.write(tmp, spec, data.data(), error);
        if (w == io_detail::OiioWritten::NoWriter) fail_no_writer(path);
        if (w == io_detail::OiioWritten::Failed)
            io_fail(path, error.empty() ? std::string("write failed (disk full?)") : error);
    });
}

bool oiio_has_writer(const std::string& path) { return oiio(path).has_writer(path); }

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
    // OpenImageIO never sees a PNG (its libpng prints its errors on stderr, past the caller):
    // one under another name is read as a PNG.
    if (has_png_signature(path)) {
        Image img;
        read_png_color(path, img);
        return img;
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

    if (has_png_signature(path)) {  // as in read_color_oiio
        Image img;
        read_png_depth(path, img, opt);
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
        fail_depth_type(path, spec.pixel_name);
    }
    return img;
}

}  // namespace deepsea::io_detail
