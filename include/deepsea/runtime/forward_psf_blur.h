#pragma once
/// \file The runtime's forward scatter from the phase function (optics/forward_psf.h):
/// F = sum_j G_j * (W_j(d) L_s), a fixed Gaussian per scale j applied to the surface radiance
/// weighted by that scale's share at each pixel's distance. Wide scales are summed into
/// box-downsampled images as they are weighted, blurred there and upsampled bilinearly.

#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/optics/forward_psf.h"

namespace deepsea {

/// Reusable state: buffers are kept between frames. prepare() weighs and blurs one frame,
/// add_row() then adds any row of F to an interleaved RGB row (thread-safe).
class ForwardPsfBlur {
public:
    explicit ForwardPsfBlur(ForwardPsf psf) : m_psf(std::move(psf)) {}

    /// surface: J/pi E (3 channels); d2: camera-to-surface distance (1 channel, <= 0 for no
    /// surface, which sends no light).
    void prepare(const Image& surface, const Image& d2);
    /// out_rgb[3u + c] = F at (u, v).
    void row(int v, float* out_rgb) const;

    const ForwardPsf& psf() const { return m_psf; }

private:
    struct Level {
        int factor = 1;  ///< downsampling factor (1: full resolution)
        int w = 0, h = 0;
        std::vector<float> partial;  ///< H rows of w x 3: each row's horizontal block sums
        std::vector<float> planes;   ///< 3 planes of w x h: the weighted image
        std::vector<float> blurred;  ///< 3 planes of w x h
        std::vector<int> x0, x1;     ///< horizontal upsampling taps per output column
        std::vector<float> ax;
    };
    void build_table(double d_max);
    ForwardPsf m_psf;
    int m_width = 0, m_height = 0;
    double m_step = 0.0;          ///< distance between table rows, metres
    int m_bins = 0;               ///< table rows - 1
    std::vector<float> m_table;   ///< m_table[(j * 3 + c) * (bins + 1) + bin] = W_j(d)
    std::vector<float> m_sharp;   ///< scale 0 (unblurred), interleaved RGB, full resolution
    std::vector<Level> m_levels;  ///< scales 1 .. S-1
    std::vector<float> m_kernel, m_norm_x, m_norm_y, m_tmp;  ///< blur scratch
};

}  // namespace deepsea
