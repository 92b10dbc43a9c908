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

#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/io/depth_formats.h"
#include "fast_codecs.h"
#include "file_checks.h"
#include "oiio_plugin.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define DEEPSEA_AVX2_ENCODER 1
#endif

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

}  // namespace

// ---------------------------------------------------------------------------------------------

float srgb_to_linear(float v) {
    // IEC 61966-2-1: linear segment below the 0.04045 knee, power 2.4 above.
    if (v <= 0.04045f) return v / 12.92f;
    return float(std::pow((double(v) + 0.055) / 1.055, 2.4));
}

namespace {

std::vector<float> make_srgb_table(int codes) {
    std::vector<float> t(std::size_t(codes) + 1);
    for (int i = 0; i <= codes; ++i) t[i] = srgb_to_linear(float(i) / float(codes));
    return t;
}

/// srgb_to_linear of every code 0 .. codes of an integer image (codes = 255 or 65535), each
/// table made on first use.
const float* srgb_decode_table(int codes) {
    if (codes == 255) {
        static const std::vector<float> t8 = make_srgb_table(255);
        return t8.data();
    }
    static const std::vector<float> t16 = make_srgb_table(65535);
    return t16.data();
}

}  // namespace

void srgb_decode(const std::uint8_t* codes, std::size_t n, float* linear) {
    const float* lut = srgb_decode_table(255);
    for (std::size_t i = 0; i < n; ++i) linear[i] = lut[codes[i]];
}

void srgb_decode(const std::uint16_t* codes, std::size_t n, float* linear) {
    const float* lut = srgb_decode_table(65535);
    for (std::size_t i = 0; i < n; ++i) linear[i] = lut[codes[i]];
}

float linear_to_srgb(float v) {
    if (v <= 0.0031308f) return v * 12.92f;
    return float(1.055 * std::pow(double(v), 1.0 / 2.4) - 0.055);
}

namespace {

/// The integer code OpenImageIO stores for a linear value v in [0, 1]: linear_to_srgb, then
/// scaled and rounded in float as its float-to-integer conversion does.
int srgb_code(float v, int codes) { return int(linear_to_srgb(v) * float(codes) + 0.5f); }

/// srgb_code of every float without a pow per pixel, and bit-identical to it: thresholds[k] is
/// the smallest float whose code is k (found once by bisection over the floats' bit patterns,
/// the code being monotone), and a table indexed by a float's upper bits gives the code at the
/// start of its bucket, from which at most a few thresholds are stepped over.
class SrgbEncoder {
public:
    explicit SrgbEncoder(int codes) : m_codes(codes), m_shift(codes > 255 ? 10 : 15) {
        m_threshold.resize(std::size_t(codes) + 2);
        const std::uint32_t one = 0x3f800000u;
        m_threshold[0] = 0;
        for (int k = 1; k <= codes; ++k) {
            std::uint32_t lo = 0, hi = one;  // code(lo) < k <= code(hi)
            while (hi - lo > 1) {
                const std::uint32_t mid = lo + (hi - lo) / 2;
                (srgb_code(from_bits(mid), codes) >= k ? hi : lo) = mid;
            }
            m_threshold[k] = hi;
        }
        m_threshold[codes + 1] = one + 1;  // never reached
        m_start.resize((one >> m_shift) + 1);
        int k = 0;
        for (std::size_t b = 0; b < m_start.size(); ++b) {
            const std::uint32_t bits = std::uint32_t(b) << m_shift;
            while (k < codes && m_threshold[k + 1] <= bits) ++k;
            m_start[b] = std::uint16_t(k);
        }
        // The most thresholds any bucket holds (its values' codes run from its start to the
        // next bucket's start): 1 for 8 bits, so a code is one table read and one comparison.
        for (std::size_t b = 0; b + 1 < m_start.size(); ++b)
            m_steps = std::max(m_steps, int(m_start[b + 1]) - int(m_start[b]));
        m_steps = std::max(m_steps, codes - int(m_start.back()));
        m_start.push_back(0);  // room for encode_vector's 32-bit reads of the last start
    }

    /// The code of a linear value: non-finite values and values <= 0 give 0, above 1 the top.
    /// Without branches on the value (noisy images would mispredict them): out-of-range values
    /// look up bucket 0 and are replaced at the end.
    int operator()(float v) const {
        std::uint32_t bits;
        std::memcpy(&bits, &v, 4);
        const bool bad =
            (bits & 0x7f800000u) == 0x7f800000u || bits >= 0x80000000u;  // NaN, inf, < 0
        const bool top = bits >= 0x3f800000u;
        const std::uint32_t x = bad || top ? 0u : bits;
        int k = m_start[x >> m_shift];
        for (int s = 0; s < m_steps; ++s) k += m_threshold[std::size_t(k) + 1] <= x ? 1 : 0;
        return bad ? 0 : top ? m_codes : k;
    }

    /// out[i] = operator()(float(in[i] * exposure)) for i < n, 8 codes at a time where the
    /// CPU has AVX2 and a code is one step from its bucket's start (8 bits): two gathers and
    /// a comparison for 8 values. Returns how many it did (a multiple of 8; 0 without AVX2).
    std::size_t encode_vector(const float* in, std::size_t n, double exposure,
                              std::uint8_t* out) const {
#if defined(DEEPSEA_AVX2_ENCODER)
        static const bool avx2 = __builtin_cpu_supports("avx2");
        if (avx2 && m_steps == 1 && m_codes == 255) return encode8_avx2(in, n, exposure, out);
#endif
        (void)in, (void)n, (void)exposure, (void)out;
        return 0;
    }

private:
#if defined(DEEPSEA_AVX2_ENCODER)
    __attribute__((target("avx2"))) std::size_t encode8_avx2(const float* in, std::size_t n,
                                                             double exposure,
                                                             std::uint8_t* out) const {
        const __m256d e = _mm256_set1_pd(exposure);
        const __m256i exponent = _mm256_set1_epi32(0x7f800000), one = _mm256_set1_epi32(0x3f800000);
        const __m256i top_code = _mm256_set1_epi32(m_codes), low16 = _mm256_set1_epi32(0xffff);
        const __m256i step = _mm256_set1_epi32(1), zero = _mm256_setzero_si256();
        const int* start = reinterpret_cast<const int*>(m_start.data());
        const int* threshold = reinterpret_cast<const int*>(m_threshold.data());
        std::size_t i = 0;
        for (; i + 8 <= n; i += 8) {
            // float(v * exposure) in double, as operator() is given it
            const __m128 lo =
                _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_cvtps_pd(_mm_loadu_ps(in + i)), e));
            const __m128 hi =
                _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_cvtps_pd(_mm_loadu_ps(in + i + 4)), e));
            const __m256i bits = _mm256_castps_si256(_mm256_set_m128(hi, lo));
            // NaN or inf (all exponent bits), or negative (sign bit: below zero as an int)
            const __m256i bad =
                _mm256_or_si256(_mm256_cmpeq_epi32(_mm256_and_si256(bits, exponent), exponent),
                                _mm256_cmpgt_epi32(zero, bits));
            const __m256i top =
                _mm256_andnot_si256(bad, _mm256_cmpgt_epi32(bits, _mm256_sub_epi32(one, step)));
            const __m256i x = _mm256_andnot_si256(_mm256_or_si256(bad, top), bits);
            // 16-bit starts read as 32-bit words at 2-byte offsets (the table has room after)
            __m256i k = _mm256_and_si256(
                _mm256_i32gather_epi32(start, _mm256_srli_epi32(x, m_shift), 2), low16);
            const __m256i next = _mm256_i32gather_epi32(threshold, _mm256_add_epi32(k, step), 4);
            k = _mm256_add_epi32(k, _mm256_andnot_si256(_mm256_cmpgt_epi32(next, x), step));
            k = _mm256_blendv_epi8(k, top_code, top);
            k = _mm256_andnot_si256(bad, k);
            const __m128i k16 =
                _mm_packus_epi32(_mm256_castsi256_si128(k), _mm256_extracti128_si256(k, 1));
            _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(k16, k16));
        }
        return i;
    }
#endif
    static float from_bits(std::uint32_t b) {
        float f;
        std::memcpy(&f, &b, 4);
        return f;
    }
    int m_codes, m_shift;
    int m_steps = 0;
    std::vector<std::uint32_t> m_threshold;  ///< as float bit patterns (ordered like the floats)
    std::vector<std::uint16_t> m_start;
};

const SrgbEncoder& srgb_encoder(int bits) {
    if (bits == 8) {
        static const SrgbEncoder e8(255);
        return e8;
    }
    static const SrgbEncoder e16(65535);
    return e16;
}

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
    // Integer codes straight from the table (OpenImageIO's float to integer conversion of
    // linear_to_srgb without a pow per value), times the exposure as apply_exposure rounds it.
    const SrgbEncoder& enc = srgb_encoder(out.bits);
    if (out.bits == 8) {
        std::uint8_t* c8 = out.codes8.data() + first;
        const std::size_t done = enc.encode_vector(linear, n, exposure, c8);
        for (std::size_t i = done; i < n; ++i)
            c8[i] = std::uint8_t(enc(float(linear[i] * exposure)));
    } else {
        std::uint16_t* c16 = out.codes16.data() + first;
        for (std::size_t i = 0; i < n; ++i)
            c16[i] = std::uint16_t(enc(float(linear[i] * exposure)));
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
