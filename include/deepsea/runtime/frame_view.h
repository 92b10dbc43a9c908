#pragma once
/// \file A frame in the caller's memory: colour and depth images described by a pointer, a size
/// and strides, read where they lie (a NumPy array, a ROS message, an OpenCV Mat, a slice of a
/// bigger buffer). Renderer::render takes them without a copy of the colour.

#include <cstddef>

#include "deepsea/optics/camera.h"

namespace deepsea {

/// How one sample of an image is stored (host byte order).
enum class SampleType { U8, U16, F32 };

/// What colour samples mean. Srgb: sRGB-encoded codes (integer samples span 0 to the type's
/// maximum; float samples 0 to 1), decoded with the sRGB curve. Linear: linear albedo (integer
/// samples divided by the type's maximum; float samples as they are).
enum class ColorEncoding { Srgb, Linear };

/// The order of a pixel's three colour samples: RGB, or BGR as OpenCV and ROS's bgr8 hold them.
enum class ChannelOrder { Rgb, Bgr };

/// A width x height colour image: pixel (u, v)'s first sample at
/// data + v * row_stride + u * pixel_stride (bytes), its three samples next to each other. A
/// fourth sample (alpha) or any padding is skipped by the strides.
struct ColorView {
    const void* data = nullptr;
    int width = 0, height = 0;
    SampleType type = SampleType::U8;
    ColorEncoding encoding = ColorEncoding::Srgb;
    ChannelOrder order = ChannelOrder::Rgb;
    std::ptrdiff_t pixel_stride = 0;  ///< bytes; 0: three samples (packed)
    std::ptrdiff_t row_stride = 0;    ///< bytes; 0: width pixels (packed)
    const char* name = nullptr;       ///< what errors call it; null: "colour view"
};

/// A width x height depth image of one sample a pixel, at data + v * row_stride +
/// u * pixel_stride (bytes). Float samples are metres; U16 samples are units of `scale` metres
/// (ROS 16UC1: millimetres). Non-finite or <= 0 (integer 0) is open water. U8 is refused.
struct DepthView {
    const void* data = nullptr;
    int width = 0, height = 0;
    SampleType type = SampleType::F32;
    DepthKind kind = DepthKind::Z;    ///< planar z, or range along the pixel's ray
    double scale = 0.001;             ///< metres per unit of an integer sample
    std::ptrdiff_t pixel_stride = 0;  ///< bytes; 0: one sample (packed)
    std::ptrdiff_t row_stride = 0;    ///< bytes; 0: width pixels (packed)
    const char* name = nullptr;       ///< what errors call it; null: "depth view"
};

/// Bytes of one sample of `type`.
std::size_t sample_bytes(SampleType type);

/// The view with its 0 strides filled in (packed) and its name set (`what` where it has none).
/// InputError naming it when the view has
/// no data, a size deepsea does not take (check_image_size), a type it cannot hold (U8
/// depth), a stride that would overlap samples or rows (negative strides included), or a
/// depth scale that is not finite and > 0.
ColorView checked(const ColorView& view, const char* what = "colour view");
DepthView checked(const DepthView& view, const char* what = "depth view");

/// InputError "<name>: pixel (u, v) G is NaN ..." for the first non-finite sample of a checked
/// float colour view (as for float colour from files, core/image.h's require_finite_color);
/// nothing for integer samples.
void require_finite_color(const ColorView& view);

}  // namespace deepsea
