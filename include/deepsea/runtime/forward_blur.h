#pragma once
/// \file Fast spatially varying Gaussian blur for forward scatter: a few fixed-sigma levels,
/// each computed on a box-downsampled copy where the blur is wide, blended per pixel by the
/// pixel's own sigma.

#include <cstddef>
#include <utility>
#include <vector>

#include "deepsea/core/image.h"

namespace deepsea {

/// Reusable state: buffers are kept between frames, so a sequence allocates once. Used in
/// two steps so that callers consume the blur row by row without a full-size output image:
/// prepare() builds the levels for one frame, blend_row() gives any row (thread-safe).
class ForwardBlur {
public:
    /// Builds the levels for a 3-channel image `in` and per-pixel blur widths
    /// sigma(p) = scale * s(p) pixels (`s` 1 channel; sigma <= 0 means no blur there, output 0).
    /// Levels are spaced by a factor sqrt(2) in sigma and bracket the frame's range; sigma is
    /// capped at max_forward_sigma_px of the image.
    void prepare(const Image& in, const Image& s, float scale);

    /// Row v of (G_{sigma(p)} * in)(p), interleaved RGB, normalised over in-image pixels like
    /// the reference renderer's exact gather. s_row is row v of the image given to prepare().
    void blend_row(int v, const float* s_row, float* out_rgb) const;

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
    void build_level(const Image& in, Level& level);
    int m_width = 0;
    float m_scale = 1.0f;
    float m_cap = 0.0f;             ///< widest sigma blurred (max_forward_sigma_px)
    std::vector<Planes> m_pyramid;  ///< m_pyramid[i], i >= 1: the input box-downsampled by 2^i
    std::vector<Level> m_levels;    ///< the first m_count are this frame's
    int m_count = 0;                ///< levels in use; 0 when no pixel is blurred
    std::vector<double> m_sigmas;   ///< this frame's level sigmas
    std::vector<float> m_kernel, m_norm_x, m_norm_y;   ///< blur_planes' scratch
    std::vector<std::pair<float, float>> m_row_range;  ///< range of s over each row
};

}  // namespace deepsea
