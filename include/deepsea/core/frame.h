#pragma once
/// \file One RGB-D frame: the unit of input the runtime, the reference and the scene share.

#include <cstdint>
#include <utility>
#include <vector>

#include "deepsea/core/image.h"

namespace deepsea {

/// Colour as PNG and JPEG files hold it: sRGB codes, interleaved RGB, 8 bits per sample (files
/// of 1 to 8 bits) or 16 (host order). A quarter (half) of the memory of the float image.
struct SrgbCodes {
    int width = 0, height = 0;
    int bits = 8;                      ///< 8 or 16
    std::vector<std::uint8_t> rgb8;    ///< bits == 8
    std::vector<std::uint16_t> rgb16;  ///< bits == 16
};

/// Linear RGB albedo (3 channels) and planar z-depth in metres (1 channel), same size. The
/// colour may instead be held as sRGB codes (`rgb` empty): the compositor decodes them a row
/// at a time, so a sequence's frames in flight keep no float copy.
struct Frame {
    Image rgb;
    Image depth;
    SrgbCodes codes;  ///< the colour when `rgb` is empty

    Frame() = default;
    Frame(Image rgb_, Image depth_) : rgb(std::move(rgb_)), depth(std::move(depth_)) {}

    bool coded() const { return rgb.empty() && codes.width > 0; }
    int color_width() const { return coded() ? codes.width : rgb.width; }
    int color_height() const { return coded() ? codes.height : rgb.height; }
};

}  // namespace deepsea
