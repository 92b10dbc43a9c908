#pragma once
/// \file Private to the runtime: a frame's colour and depth as the compositor reads them, from
/// an owned Frame or from the caller's views (runtime/frame_view.h).

#include <cstdint>
#include <string>
#include <vector>

#include "deepsea/core/frame.h"
#include "deepsea/core/image.h"
#include "deepsea/runtime/frame_view.h"

namespace deepsea {

/// The view of a Frame's colour: its float image (linear) or its sRGB codes. InputError when
/// the frame holds neither a 3-channel image nor codes that fill their size.
ColorView color_view(const Frame& frame);

/// A thread's buffers for color_row (sized on first use, reused after).
struct ColorRowBuffer {
    std::vector<float> linear;
    std::vector<std::uint8_t> u8;
    std::vector<std::uint16_t> u16;
    std::vector<float> f32;
};

/// Row v of a checked colour view as 3 x width linear RGB floats: a pointer into the view's
/// own memory where it already is that (packed linear RGB float), otherwise decoded into
/// `buf`. The sRGB curve is colour's (srgb_decode, srgb_to_linear); integer linear samples are
/// divided by the type's maximum.
const float* color_row(const ColorView& view, int v, ColorRowBuffer& buf);

/// A checked depth view as the compositor's float depth image (`out`, resized): float samples
/// as they are, integer ones times the scale (as io reads integer depth files).
void depth_image(const DepthView& view, Image& out);

}  // namespace deepsea
