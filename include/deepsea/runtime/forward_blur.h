#pragma once
/// \file Fast spatially varying Gaussian blur for forward scatter: a few fixed-sigma levels,
/// each computed on a box-downsampled copy, blended per pixel by its own sigma.

#include <vector>

#include "deepsea/core/image.h"

namespace deepsea {

/// Reusable state: buffers are kept between frames so a sequence allocates once.
class ForwardBlur {
public:
    /// out(p) = (G_{sigma(p)} * in)(p) for a 3-channel image, with sigma in pixels per pixel
    /// (1 channel; <= 0 leaves the pixel at 0). Normalised over in-image pixels, as the
    /// reference renderer's exact gather. Levels are spaced by a factor sqrt(2) in sigma.
    void apply(const Image& in, const Image& sigma, Image& out);

private:
    struct Level {
        double sigma = 0.0;  ///< full-resolution sigma, pixels
        int factor = 1;      ///< downsampling factor
        int w = 0, h = 0;
        std::vector<float> rgbw;  ///< 4 planes: blurred R, G, B and the in-image weight
    };
    void build_level(Level& level, const Image& in);
    std::vector<Level> m_levels;
    std::vector<std::vector<float>> m_pyramid;  ///< box-downsampled R, G, B, weight planes
    std::vector<int> m_pyramid_w, m_pyramid_h;
};

}  // namespace deepsea
