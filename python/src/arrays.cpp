#include "arrays.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/image_io.h"

namespace deepsea::python {

namespace {

/// Image rows per task when converting arrays: enough work to be worth a task.
constexpr std::size_t kRowGrain = 32;

std::string dtype_name(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) {
        if (i) s += ", ";
        s += std::to_string(a.shape(i));
    }
    return s + (a.ndim() == 1 ? ",)" : ")");
}

/// The element type of `a`, if the module reads it in this role.
bool elem_of(const py::array& a, bool color, Elem& out) {
    const py::dtype dt = a.dtype();
    if (!dt.attr("isnative").cast<bool>()) return false;  // byte-swapped: numpy can convert
    const char kind = dt.kind();
    const py::ssize_t size = dt.itemsize();
    if (kind == 'u' && size == 1 && color) {
        out = Elem::U8;
    } else if (kind == 'u' && size == 2) {
        out = Elem::U16;
    } else if (kind == 'f' && size == 4) {
        out = Elem::F32;
    } else if (kind == 'f' && size == 8) {
        out = Elem::F64;
    } else {
        return false;
    }
    return true;
}

ArrayIn inspect(const py::handle& obj, const std::string& what, bool color) {
    const py::array a = py::array::ensure(obj);  // numpy.asarray
    if (!a) throw py::error_already_set();
    ArrayIn in;
    if (!elem_of(a, color, in.elem)) {
        throw InputError(what + ": dtype " + dtype_name(a) + " is not supported; give " +
                         (color ? "uint8 or uint16 (sRGB codes) or float32 or float64 (linear)"
                                : "float32 or float64 (metres) or uint16 (times depth_scale)"));
    }
    const py::ssize_t nd = a.ndim();
    const py::ssize_t c = nd == 3 ? a.shape(2) : 1;
    const bool shape_ok = (nd == 2 || nd == 3) && (color ? (c == 1 || c == 3 || c == 4) : c == 1);
    if (!shape_ok) {
        throw InputError(
            what + ": shape " + shape_text(a) + " is not an image; give " +
            (color ? "(H, W, 3) RGB, (H, W, 4) RGBA or (H, W) grey" : "(H, W) or (H, W, 1)"));
    }
    check_image_size(a.shape(1), a.shape(0), c, what);
    in.height = int(a.shape(0));
    in.width = int(a.shape(1));
    in.channels = int(c);
    // A C-contiguous view of the same memory, or numpy's contiguous copy of a strided view.
    in.array = py::array::ensure(a, py::array::c_style);
    if (!in.array) throw py::error_already_set();
    return in;
}

/// Converts n elements to linear floats in the array's encoding, as the compositor's
/// color_row decodes a view (runtime/frame_view.cpp).
void to_linear(const ArrayIn& in, std::size_t offset, std::size_t n, float* out) {
    const bool srgb = in.encoding == ColorEncoding::Srgb;
    switch (in.elem) {
        case Elem::U8: {
            const std::uint8_t* src = static_cast<const std::uint8_t*>(in.data()) + offset;
            if (srgb) {
                srgb_decode(src, n, out);
            } else {
                for (std::size_t i = 0; i < n; ++i) out[i] = float(src[i]) / 255.0f;
            }
            return;
        }
        case Elem::U16: {
            const std::uint16_t* src = static_cast<const std::uint16_t*>(in.data()) + offset;
            if (srgb) {
                srgb_decode(src, n, out);
            } else {
                for (std::size_t i = 0; i < n; ++i) out[i] = float(src[i]) / 65535.0f;
            }
            return;
        }
        case Elem::F32:
            std::memcpy(out, static_cast<const float*>(in.data()) + offset, n * sizeof(float));
            break;
        case Elem::F64: {
            const double* src = static_cast<const double*>(in.data()) + offset;
            for (std::size_t i = 0; i < n; ++i) out[i] = float(src[i]);
            break;
        }
    }
    if (srgb) {
        for (std::size_t i = 0; i < n; ++i) out[i] = srgb_to_linear(out[i]);
    }
}

/// Sets the size of `img`, keeping its memory when the size is unchanged.
void reshape(Image& img, int width, int height, int channels) {
    img.width = width;
    img.height = height;
    img.channels = channels;
    img.data.resize(std::size_t(width) * height * channels);
}

}  // namespace

ArrayIn inspect_color(const py::handle& obj, const std::string& what) {
    ArrayIn in = inspect(obj, what, true);
    in.encoding =
        in.elem == Elem::U8 || in.elem == Elem::U16 ? ColorEncoding::Srgb : ColorEncoding::Linear;
    return in;
}

void set_color_encoding(ArrayIn& in, const py::handle& encoding, const std::string& what) {
    const bool floats = in.elem == Elem::F32 || in.elem == Elem::F64;
    if (encoding.is_none()) {
        if (floats) {
            throw InputError(what + ": " + dtype_name(in.array) +
                             " colour needs its encoding stated: encoding='srgb' (sRGB values "
                             "in [0, 1], as a PNG read as float) or encoding='linear' (linear "
                             "albedo, as EXR files)");
        }
        in.encoding = ColorEncoding::Srgb;  // 8- and 16-bit codes, as the CLI reads PNG
        return;
    }
    const std::string e = py::str(encoding).cast<std::string>();
    if (!py::isinstance<py::str>(encoding) || (e != "srgb" && e != "linear")) {
        throw ConfigError("encoding: expected 'srgb' or 'linear', got " +
                          py::repr(encoding).cast<std::string>());
    }
    in.encoding = e == "srgb" ? ColorEncoding::Srgb : ColorEncoding::Linear;
}

ArrayIn inspect_depth(const py::handle& obj, const std::string& what) {
    return inspect(obj, what, false);
}

bool color_view_of(const ArrayIn& in, ColorView& out) {
    if (in.channels < 3 || in.elem == Elem::F64) return false;
    out = ColorView{};
    out.data = in.data();
    out.width = in.width;
    out.height = in.height;
    out.type = in.elem == Elem::U8    ? SampleType::U8
               : in.elem == Elem::U16 ? SampleType::U16
                                      : SampleType::F32;
    out.encoding = in.encoding;
    out.pixel_stride = std::ptrdiff_t(in.channels * sample_bytes(out.type));  // C-contiguous
    return true;
}

bool depth_view_of(const ArrayIn& in, double scale, DepthView& out) {
    if (in.elem != Elem::F32 && in.elem != Elem::U16) return false;
    out = DepthView{};
    out.data = in.data();
    out.width = in.width;
    out.height = in.height;
    out.type = in.elem == Elem::U16 ? SampleType::U16 : SampleType::F32;
    out.scale = scale;
    return true;
}

void fill_color(const ArrayIn& in, Image& out, int threads, bool albedo) {
    reshape(out, in.width, in.height, 3);
    const int c = in.channels;
    const std::size_t row_in = std::size_t(in.width) * c;
    parallel_for(std::size_t(in.height),
                 [&](std::size_t v0, std::size_t v1) {
                     if (c == 3) {
                         to_linear(in, v0 * row_in, (v1 - v0) * row_in, out.row(int(v0)));
                         return;
                     }
                     // Grey or RGBA: one row at a time through a small buffer.
                     std::vector<float> row(row_in);
                     for (std::size_t v = v0; v < v1; ++v) {
                         to_linear(in, v * row_in, row_in, row.data());
                         float* dst = out.row(int(v));
                         for (int u = 0; u < in.width; ++u) {
                             for (int k = 0; k < 3; ++k) {
                                 dst[u * 3 + k] = row[std::size_t(u) * c + (c == 1 ? 0 : k)];
                             }
                         }
                     }
                 },
                 {threads, kRowGrain});
    // Float albedo: one NaN would darken the whole frame (core/image.h).
    if (albedo && (in.elem == Elem::F32 || in.elem == Elem::F64)) require_finite_color(out, "rgb");
}

void fill_depth(const ArrayIn& in, double scale, Image& out, int threads) {
    reshape(out, in.width, in.height, 1);
    const std::size_t w = std::size_t(in.width);
    parallel_for(
        std::size_t(in.height),
        [&](std::size_t v0, std::size_t v1) {
            const std::size_t i0 = v0 * w, n = (v1 - v0) * w;
            float* dst = out.data.data() + i0;
            switch (in.elem) {
                case Elem::U16: {
                    const std::uint16_t* src = static_cast<const std::uint16_t*>(in.data()) + i0;
                    for (std::size_t i = 0; i < n; ++i) dst[i] = float(src[i] * scale);
                    break;
                }
                case Elem::F32:
                    std::memcpy(dst, static_cast<const float*>(in.data()) + i0, n * sizeof(float));
                    break;
                case Elem::F64: {
                    const double* src = static_cast<const double*>(in.data()) + i0;
                    for (std::size_t i = 0; i < n; ++i) dst[i] = float(src[i]);
                    break;
                }
                case Elem::U8:
                    throw InputError("8-bit depth is not supported");  // inspect_depth refuses
            }
        },
        {threads, kRowGrain});
}

std::vector<float> BufferPool::take(std::size_t n) {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (std::size_t i = 0; i < m_free.size(); ++i) {
        if (m_free[i].size() == n) {
            std::vector<float> out = std::move(m_free[i]);
            m_free.erase(m_free.begin() + std::ptrdiff_t(i));
            return out;
        }
    }
    return {};
}

void BufferPool::give(std::vector<float>&& buffer) {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_free.size() >= kMaxBuffers) m_free.erase(m_free.begin());  // the oldest size goes
    m_free.push_back(std::move(buffer));
}

void reuse(Image& img, int width, int height, int channels, BufferPool& pool) {
    std::vector<float> buffer = pool.take(std::size_t(width) * height * channels);
    if (buffer.empty()) return;
    img.width = width;
    img.height = height;
    img.channels = channels;
    img.data = std::move(buffer);
}

namespace {

/// What an array's capsule owns: its pixels, and where they go when it is freed.
struct Lent {
    std::vector<float> pixels;
    std::weak_ptr<BufferPool> pool;
};

}  // namespace

py::array to_array(Image&& img, const std::shared_ptr<BufferPool>& pool) {
    auto* lent = new Lent{std::move(img.data), pool};
    const py::capsule owner(lent, [](void* p) {
        std::unique_ptr<Lent> l(static_cast<Lent*>(p));
        if (auto pool = l->pool.lock()) pool->give(std::move(l->pixels));
    });
    std::vector<py::ssize_t> shape{img.height, img.width};
    if (img.channels != 1) shape.push_back(img.channels);
    img = Image();
    return py::array_t<float>(shape, lent->pixels.data(), owner);
}

}  // namespace deepsea::python
