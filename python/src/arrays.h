#pragma once
// NumPy arrays in and out of deepsea's Images. Reading an array takes two steps: inspect()
// (with the GIL: dtype, shape, a C-contiguous view) and then fill the Image (without the GIL:
// plain C++ on the array's memory). Output layers move their pixels into the array they
// return: no copy.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/runtime/frame_view.h"

namespace deepsea::python {

namespace py = pybind11;

/// Element types the module reads.
enum class Elem { U8, U16, F32, F64 };

/// A C-contiguous array of height x width x channels elements, checked, and the reference
/// that keeps its memory alive.
struct ArrayIn {
    py::array array;  ///< C-contiguous (numpy's copy if the caller's was not)
    Elem elem = Elem::F32;
    /// What colour samples mean: inspect_color sets sRGB for integers and linear for floats
    /// (radiance); a frame's colour takes the caller's word (set_color_encoding).
    ColorEncoding encoding = ColorEncoding::Linear;
    int height = 0, width = 0, channels = 0;
    const void* data() const { return array.data(); }
};

/// Checks a colour array (or anything numpy.asarray takes, such as nested lists): (H, W, 3) RGB,
/// (H, W, 4) RGBA (alpha dropped), (H, W) or (H, W, 1) grey; uint8 / uint16 (sRGB codes) or float32
/// / float64 (linear). InputError naming `what` otherwise. Needs the GIL.
ArrayIn inspect_color(const py::handle& obj, const std::string& what);

/// Sets the encoding of a frame's colour from `encoding` (None, "srgb" or "linear"). Integer
/// samples are sRGB codes unless told "linear" (as the CLI reads 8- and 16-bit files); float
/// samples have no default: sRGB values in [0, 1] (a PNG read as float by another library)
/// taken as linear albedo would be silently wrong, so None is an InputError naming `what`.
void set_color_encoding(ArrayIn& in, const py::handle& encoding, const std::string& what);

/// Checks a depth array: (H, W) or (H, W, 1); float32 / float64 (metres) or uint16 (units of
/// the depth scale). InputError naming `what` otherwise. Needs the GIL.
ArrayIn inspect_depth(const py::handle& obj, const std::string& what);

/// A view of the array's own memory as the renderer reads it (runtime/frame_view.h), where it
/// can: colour as uint8 / uint16 / float32 samples in the array's encoding, RGB or RGBA (alpha
/// skipped); depth as float32 metres or uint16 units of `scale` metres. False for the others
/// (grey, float64), which fill_color / fill_depth convert. The view is valid while `in` lives.
bool color_view_of(const ArrayIn& in, ColorView& out);
bool depth_view_of(const ArrayIn& in, double scale, DepthView& out);

/// Fills `out` with linear RGB (3 channels) in the array's encoding, decoded as the compositor
/// decodes a colour view of the same samples (sRGB codes: as read_color decodes files). Reuses
/// out's memory. Parallel over rows on `threads` workers (0: all cores). No Python calls: may run
/// without the GIL. As albedo (a frame's colour), float values must be finite: InputError "rgb:
/// pixel (u, v) ..." otherwise (require_finite_color).
void fill_color(const ArrayIn& in, Image& out, int threads = 0, bool albedo = true);

/// Fills `out` with one-channel depth in metres: floats as they are, uint16 times `scale` (as
/// a 16-bit PNG depth image). Reuses out's memory. Parallel as fill_color. No Python calls.
void fill_depth(const ArrayIn& in, double scale, Image& out, int threads = 0);

/// Pixel buffers lent to NumPy arrays come back here when the arrays are freed, so that the
/// next frame of the same size reuses them (no allocation, no page faults, no zero fill): in a
/// loop that drops each frame's layers before the next, nothing is allocated after the first
/// frames. Thread-safe; holds at most kMaxBuffers.
class BufferPool {
public:
    static constexpr std::size_t kMaxBuffers = 32;
    /// A buffer of exactly n floats (contents undefined), or an empty vector if none is free.
    std::vector<float> take(std::size_t n);
    void give(std::vector<float>&& buffer);

private:
    std::mutex m_mutex;
    std::vector<std::vector<float>> m_free;
};

/// Gives `img` the pool's buffer for width x height x channels, if it has one, so that
/// Layers::resize keeps it.
void reuse(Image& img, int width, int height, int channels, BufferPool& pool);

/// The image as a float32 array that owns its pixels (moved out of `img`, which is left
/// empty): (H, W, C), or (H, W) for one channel. When the array is freed its buffer goes back
/// to `pool`, if the pool still exists. Needs the GIL.
py::array to_array(Image&& img, const std::shared_ptr<BufferPool>& pool = {});

}  // namespace deepsea::python
