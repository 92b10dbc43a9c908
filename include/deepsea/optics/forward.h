#pragma once
/// \file Jaffe-McGlamery forward scatter terms (DESIGN.md section 2):
/// F = w(d2) * (G_sigma(d2) * D), the blur done by the renderer, these two factors here.

#include <cmath>

#include "deepsea/core/vec.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// Weight w(d) = exp(-G d) - exp(-c d) per channel for camera-to-surface distance d (metres).
inline Rgb forward_weight(const ForwardScatter& fs, const Rgb& c, double d) {
    return exp(fs.G * -d) - exp(c * -d);
}

/// Blur standard deviation in pixels, sigma_px = fx * k * d, for distance d (metres).
inline double forward_sigma_px(const ForwardScatter& fs, double fx, double d) {
    return fx * fs.k * d;
}

}  // namespace deepsea
