#pragma once
/// \file Jaffe-McGlamery forward scatter terms (docs/model.md, "Forward scatter"):
/// F = w(d2) * (G_sigma(d2) * L_s), L_s = J/pi E the surface radiance before the path to the
/// camera (w carries that path: blurring D would attenuate twice); the blur is done by the
/// renderer, these two factors here.

#include <cmath>

#include "deepsea/core/vec.h"
#include "deepsea/optics/transmission.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// Weight w(d) = exp(-G d) - exp(-c d) of the blurred direct signal, one channel, for
/// camera-to-surface distance d (metres), G <= c (1/m): 0 at d = 0 and where G = c. The
/// reference (double) and the runtime's rows (float, `#pragma omp simd`) both call this;
/// exp(-c d) is the transmission, which a caller that also needs it shares (GCC merges the
/// two calls).
template <class T>
inline T forward_weight(T G, T c, T d) {
    using std::exp;
    return exp(-G * d) - transmission(c, d);
}

/// forward_weight per channel.
inline Rgb forward_weight(const ForwardScatter& fs, const Rgb& c, double d) {
    return {forward_weight(fs.G.r, c.r, d), forward_weight(fs.G.g, c.g, d),
            forward_weight(fs.G.b, c.b, d)};
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
