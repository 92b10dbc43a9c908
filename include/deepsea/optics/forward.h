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

/// The widest blur the renderers apply to a width x height image: its larger side. A wider
/// Gaussian is flat over the image, and surfaces that far away get a weight w(d) of ~0, so
/// capping there changes nothing visible while keeping very distant surfaces cheap.
inline double max_forward_sigma_px(int width, int height) {
    return double(width > height ? width : height);
}

}  // namespace deepsea
