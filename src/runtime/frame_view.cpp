#include "deepsea/runtime/frame_view.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "deepsea/colour/srgb.h"
#include "deepsea/core/error.h"
#include "frame_input.h"

namespace deepsea {

namespace {

/// The strides of a view of `samples` samples a pixel, 0s filled in, checked to hold each
/// pixel's samples apart and each row apart, aligned for the sample type.
void check_layout(const void* data, int width, int height, SampleType type, int samples,
                  std::ptrdiff_t& pixel_stride, std::ptrdiff_t& row_stride, const char* what) {
    const std::string name(what);
    if (!data) throw InputError(name + ": no data (null pointer)");
    check_image_size(width, height, samples, name);
    const auto size = std::ptrdiff_t(sample_bytes(type));
    if (pixel_stride == 0) pixel_stride = samples * size;
    if (row_stride == 0) row_stride = width * pixel_stride;
    if (pixel_stride < samples * size) {
        throw InputError(name + ": pixel stride " + std::to_string(pixel_stride) +
                         " bytes is less than a pixel's " + std::to_string(samples * size));
    }
    if (row_stride < width * pixel_stride) {
        throw InputError(name + ": row stride " + std::to_string(row_stride) +
                         " bytes is less than a row's " + std::to_string(width * pixel_stride));
    }
    if (reinterpret_cast<std::uintptr_t>(data) % std::uintptr_t(size) != 0 ||
        pixel_stride % size != 0 || row_stride % size != 0) {
        throw InputError(name + ": data and strides must be multiples of the sample size (" +
                         std::to_string(size) + " bytes)");
    }
}

const unsigned char* row_of(const void* data, std::ptrdiff_t row_stride, int v) {
    return static_cast<const unsigned char*>(data) + std::ptrdiff_t(v) * row_stride;
}

/// Row v's samples of type T in RGB order, packed into `out`.
template <class T>
const T* gather(const ColorView& c, int v, std::vector<T>& out) {
    const unsigned char* row = row_of(c.data, c.row_stride, v);
    out.resize(3 * std::size_t(c.width));
    const bool bgr = c.order == ChannelOrder::Bgr;
    for (int u = 0; u < c.width; ++u) {
        const auto* px = reinterpret_cast<const T*>(row + std::ptrdiff_t(u) * c.pixel_stride);
        out[3 * std::size_t(u)] = px[bgr ? 2 : 0];
        out[3 * std::size_t(u) + 1] = px[1];
        out[3 * std::size_t(u) + 2] = px[bgr ? 0 : 2];
    }
    return out.data();
}

template <class T>
const T* samples(const ColorView& c, int v, std::vector<T>& buf) {
    const bool packed =
        c.order == ChannelOrder::Rgb && c.pixel_stride == 3 * std::ptrdiff_t(sizeof(T));
    return packed ? reinterpret_cast<const T*>(row_of(c.data, c.row_stride, v)) : gather(c, v, buf);
}

}  // namespace

std::size_t sample_bytes(SampleType type) {
    switch (type) {
        case SampleType::U8:
            return 1;
        case SampleType::U16:
            return 2;
        case SampleType::F32:
            return 4;
    }
    throw InputError("unknown sample type");
}

ColorView checked(const ColorView& view, const char* what) {
    ColorView c = view;
    if (!c.name) c.name = what;
    check_layout(c.data, c.width, c.height, c.type, 3, c.pixel_stride, c.row_stride, c.name);
    return c;
}

DepthView checked(const DepthView& view, const char* what) {
    DepthView d = view;
    if (!d.name) d.name = what;
    if (d.type == SampleType::U8) {
        throw InputError(std::string(d.name) +
                         ": 8-bit depth is refused (too coarse for metres; "
                         "give float metres or 16-bit units)");
    }
    if (d.type == SampleType::U16 && !(std::isfinite(d.scale) && d.scale > 0.0)) {
        throw InputError(std::string(d.name) + ": depth scale " + std::to_string(d.scale) +
                         " must be finite and > 0 (metres per unit)");
    }
    check_layout(d.data, d.width, d.height, d.type, 1, d.pixel_stride, d.row_stride, d.name);
    return d;
}

ColorView color_view(const Frame& f) {
    ColorView c;
    if (f.coded()) {
        const SrgbCodes& codes = f.codes;
        const std::size_t n = 3 * std::size_t(codes.width) * std::size_t(codes.height);
        const bool wide = codes.bits == 16;
        if ((wide ? codes.rgb16.size() : codes.rgb8.size()) != n) {
            throw InputError("frame's colour codes do not fill its " + std::to_string(codes.width) +
                             "x" + std::to_string(codes.height) + " pixels");
        }
        c.data = wide ? static_cast<const void*>(codes.rgb16.data()) : codes.rgb8.data();
        c.type = wide ? SampleType::U16 : SampleType::U8;
        c.width = codes.width;
        c.height = codes.height;
    } else {
        if (f.rgb.channels != 3) throw InputError("frame needs a 3-channel colour image");
        c.data = f.rgb.data.data();
        c.type = SampleType::F32;
        c.encoding = ColorEncoding::Linear;
        c.width = f.rgb.width;
        c.height = f.rgb.height;
    }
    c.pixel_stride = 3 * std::ptrdiff_t(sample_bytes(c.type));
    c.row_stride = c.width * c.pixel_stride;
    return c;
}

const float* color_row(const ColorView& c, int v, ColorRowBuffer& buf) {
    const std::size_t n = 3 * std::size_t(c.width);
    const bool srgb = c.encoding == ColorEncoding::Srgb;
    if (c.type == SampleType::F32) {
        const float* x = samples(c, v, buf.f32);
        if (!srgb) return x;
        buf.linear.resize(n);
        for (std::size_t i = 0; i < n; ++i) buf.linear[i] = srgb_to_linear(x[i]);
        return buf.linear.data();
    }
    buf.linear.resize(n);
    float* out = buf.linear.data();
    if (c.type == SampleType::U8) {
        const std::uint8_t* x = samples(c, v, buf.u8);
        if (srgb) {
            srgb_decode(x, n, out);
        } else {
            for (std::size_t i = 0; i < n; ++i) out[i] = float(x[i]) / 255.0f;
        }
    } else {
        const std::uint16_t* x = samples(c, v, buf.u16);
        if (srgb) {
            srgb_decode(x, n, out);
        } else {
            for (std::size_t i = 0; i < n; ++i) out[i] = float(x[i]) / 65535.0f;
        }
    }
    return out;
}

void require_finite_color(const ColorView& c) {
    if (c.type != SampleType::F32) return;
    const long long none = (long long)c.width * c.height;
    const long long bad = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, c.height), none,
        [&](const tbb::blocked_range<int>& r, long long first) {
            ColorRowBuffer buf;
            for (int v = r.begin(); v < r.end(); ++v) {
                if ((long long)v * c.width >= first) break;
                const float* x = samples(c, v, buf.f32);
                for (int i = 0; i < 3 * c.width; ++i) {
                    if (!std::isfinite(x[i]))
                        return std::min(first, (long long)v * c.width * 3 + i);
                }
            }
            return first;
        },
        [](long long a, long long b) { return std::min(a, b); });
    if (bad == none) return;
    const long long u = bad / 3 % c.width, v = bad / 3 / c.width;
    ColorRowBuffer buf;
    const float* x = samples(c, int(v), buf.f32);
    throw_non_finite_color(c.name, int(u), int(v), int(bad % 3), x[3 * u + bad % 3]);
}

void depth_image(const DepthView& d, Image& out) {
    if (out.width != d.width || out.height != d.height || out.channels != 1)
        out = Image(d.width, d.height, 1);
    for (int v = 0; v < d.height; ++v) {
        const unsigned char* row = row_of(d.data, d.row_stride, v);
        float* z = out.row(v);
        if (d.type == SampleType::F32) {
            if (d.pixel_stride == 4) {
                std::memcpy(z, row, 4 * std::size_t(d.width));
            } else {
                for (int u = 0; u < d.width; ++u)
                    std::memcpy(&z[u], row + std::ptrdiff_t(u) * d.pixel_stride, 4);
            }
        } else {
            for (int u = 0; u < d.width; ++u) {
                std::uint16_t x;
                std::memcpy(&x, row + std::ptrdiff_t(u) * d.pixel_stride, 2);
                z[u] = float(double(x) * d.scale);  // as io reads 16-bit depth files
            }
        }
    }
}

}  // namespace deepsea
