#pragma once
/// \file Fast spatially varying Gaussian blur for forward scatter: a few fixed-sigma levels,
/// each computed on a box-downsampled copy where the blur is wide, blended per pixel by the
/// pixel's own sigma.

#include <utility>
#include <vector>

#include "deepsea/core/image.h"

namespace deepsea {

/// Reusable state: buffers are kept between frames, so a sequence allocates once.
class ForwardBlur {
public:
    /// out(p) = (G_{sigma(p)} * in)(p) for a 3-channel image, sigma in pixels per pixel
    /// (1 channel; <= 0 leaves the pixel at 0). Normalised over in-image pixels, like the
    /// reference renderer's exact gather. Levels are spaced by a factor sqrt(2) in sigma.
    void apply(const Image& in, const Image& sigma, Image& out);

private:
    /// 3 planes (R, G, B) of one resolution.
    struct Planes {
        int w = 0, h = 0;
        std::vector<float> data;
        float* plane(int c) { return data.data() + std::size_t(c) * w * h; }
        const float* plane(int c) const { return data.data() + std::size_t(c) * w * h; }
    };
    struct Level {
        double sigma = 0.0;  ///< full-resolution sigma, pixels
        int factor = 1;      ///< downsampling factor of `blurred`
        Planes blurred;
        std::vector<int> x0, x1;  ///< horizontal upsampling taps per output column
        std::vector<float> ax;
        int taps_width = 0, taps_factor = 0;  ///< what x0, x1, ax were made for
    };
    void build_level(Level& level);
    void blend(const Image& sigma, Image& out);
    std::vector<Planes> m_pyramid;  ///< m_pyramid[i]: the input box-downsampled by 2^i
    std::vector<Level> m_levels;
    std::vector<float> m_tmp;
    std::vector<std::pair<float, float>> m_row_range;  ///< sigma range of each row
};

}  // namespace deepsea
