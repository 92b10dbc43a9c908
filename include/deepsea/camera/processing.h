#pragma once
/// \file Colour processing (docs/camera.md, "Processing"): from linear DN to display values.

#include "deepsea/camera/model.h"
#include "deepsea/core/fast_math.h"

namespace deepsea {

/// The sRGB encoding (IEC 61966-2-1) of a linear value in [0, 1]: 12.92 x up to 0.0031308,
/// then 1.055 x^(1/2.4) - 0.055.
template <class F>
[[gnu::always_inline]] inline F srgb_curve(F x) {
    return x <= F(0.0031308) ? F(12.92) * x : F(1.055) * fast_pow(x, F(1.0 / 2.4)) - F(0.055);
}

/// The gamma curve at a linear value in [0, 1]: x^(1/gamma).
template <class F>
[[gnu::always_inline]] inline F gamma_encode(F x, F inv_gamma) {
    return fast_pow(x, inv_gamma);
}

/// Grey-world gains from a frame's mean linear values (DN above the black level) per channel:
/// mean_G / mean_c, so that the balanced means are equal. A channel with no signal keeps 1.
Rgb grey_world_gains(const Rgb& channel_means);

}  // namespace deepsea
