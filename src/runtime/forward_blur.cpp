#include "deepsea/runtime/forward_blur.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace deepsea {

namespace {

constexpr double kLevelRatio = 1.4142135623730951;  // sqrt(2)

/// Separable Gaussian of `sigma` (pixels of this level) over 4 planes of w x h, zero outside.
void blur_planes(std::vector<float>& planes, int w, int h, double sigma) {
    const int r = std::max(1, int(std::ceil(3.0 * sigma)));
    std::vector<float> g(2 * r + 1);
    for (int i = -r; i <= r; ++i) g[i + r] = float(std::exp(-0.5 * i * i / (sigma * sigma)));
    const std::size_t plane = std::size_t(w) * h;
    std::vector<float> tmp(planes.size());
    // horizontal: rows are independent
    tbb::parallel_for(0, 4 * h, [&](int row) {
        const float* src = planes.data() + std::size_t(row) * w;
        float* dst = tmp.data() + std::size_t(row) * w;
        for (int x = 0; x < w; ++x) {
            const int k0 = std::max(-r, -x), k1 = std::min(r, w - 1 - x);
            float s = 0.0f;
            for (int k = k0; k <= k1; ++k) s += g[k + r] * src[x + k];
            dst[x] = s;
        }
    });
    // vertical: accumulate whole rows so the inner loop runs along x (vectorises)
    tbb::parallel_for(0, 4 * h, [&](int prow) {
        const int p = prow / h, y = prow % h;
        float* dst = planes.data() + p * plane + std::size_t(y) * w;
        std::fill(dst, dst + w, 0.0f);
        const int k0 = std::max(-r, -y), k1 = std::min(r, h - 1 - y);
        for (int k = k0; k <= k1; ++k) {
            const float gk = g[k + r];
            const float* src = tmp.data() + p * plane + std::size_t(y + k) * w;
            for (int x = 0; x < w; ++x) dst[x] += gk * src[x];
        }
    });
}

/// Bilinear sample of plane `p` of a level at full-resolution pixel (u, v).
inline float sample(const std::vector<float>& planes, int w, int h, int f, int p, int u, int v) {
    const float fx = (u + 0.5f) / f - 0.5f, fy = (v + 0.5f) / f - 0.5f;
    const int x0 = std::clamp(int(std::floor(fx)), 0, w - 1), y0 = std::clamp(int(std::floor(fy)), 0, h - 1);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const float ax = std::clamp(fx - x0, 0.0f, 1.0f), ay = std::clamp(fy - y0, 0.0f, 1.0f);
    const float* q = planes.data() + std::size_t(p) * w * h;
    const float top = q[y0 * w + x0] + ax * (q[y0 * w + x1] - q[y0 * w + x0]);
    const float bot = q[y1 * w + x0] + ax * (q[y1 * w + x1] - q[y1 * w + x0]);
    return top + ay * (bot - top);
}

}  // namespace

void ForwardBlur::build_level(Level& L, const Image& in) {
    // Downsample while the reduced sigma stays >= 1.5 px, so the kernel keeps its shape.
    int f = 1, lvl = 0;
    while (L.sigma / (2 * f) >= 1.5 && lvl + 1 < int(m_pyramid.size())) {
        f *= 2;
        ++lvl;
    }
    L.factor = f;
    L.w = m_pyramid_w[lvl];
    L.h = m_pyramid_h[lvl];
    L.rgbw = m_pyramid[lvl];
    // Box downsampling by f and bilinear upsampling already spread the signal by about
    // (f^2 - 1)/12 + f^2/12 px^2; the level's Gaussian supplies the rest of the variance.
    const double spent = (2.0 * f * f - 1.0) / 12.0;
    const double rest = std::sqrt(std::max(L.sigma * L.sigma - spent, 0.09)) / f;
    blur_planes(L.rgbw, L.w, L.h, rest);
}

void ForwardBlur::apply(const Image& in, const Image& sigma, Image& out) {
    const int W = in.width, H = in.height;
    if (out.width != W || out.height != H || out.channels != 3) out = Image(W, H, 3);
    double smin = 1e30, smax = 0.0;
    for (float s : sigma.data) {
        if (s > 0.0f) {
            smin = std::min(smin, double(s));
            smax = std::max(smax, double(s));
        }
    }
    std::fill(out.data.begin(), out.data.end(), 0.0f);
    if (smax <= 0.0) return;

    // Pyramid level 0: the image itself as planes plus an all-ones weight plane.
    const int max_levels = 8;
    m_pyramid.resize(max_levels);
    m_pyramid_w.assign(max_levels, 0);
    m_pyramid_h.assign(max_levels, 0);
    m_pyramid[0].resize(4 * std::size_t(W) * H);
    m_pyramid_w[0] = W;
    m_pyramid_h[0] = H;
    const std::size_t plane0 = std::size_t(W) * H;
    for (std::size_t i = 0; i < plane0; ++i) {
        for (int c = 0; c < 3; ++c) m_pyramid[0][c * plane0 + i] = in.data[3 * i + c];
        m_pyramid[0][3 * plane0 + i] = 1.0f;
    }
    int used = 1;
    for (int l = 1; l < max_levels; ++l) {
        const int pw = m_pyramid_w[l - 1], ph = m_pyramid_h[l - 1];
        if (pw < 8 || ph < 8) break;
        const int w = (pw + 1) / 2, h = (ph + 1) / 2;
        m_pyramid_w[l] = w;
        m_pyramid_h[l] = h;
        m_pyramid[l].assign(4 * std::size_t(w) * h, 0.0f);
        const std::vector<float>& s = m_pyramid[l - 1];
        for (int p = 0; p < 4; ++p) {
            for (int y = 0; y < h; ++y) {
                for (int x = 0; x < w; ++x) {
                    float acc = 0.0f;
                    for (int dy = 0; dy < 2; ++dy) {
                        for (int dx = 0; dx < 2; ++dx) {
                            const int sx = 2 * x + dx, sy = 2 * y + dy;
                            if (sx < pw && sy < ph) acc += s[(std::size_t(p) * ph + sy) * pw + sx];
                        }
                    }
                    m_pyramid[l][(std::size_t(p) * h + y) * w + x] = 0.25f * acc;
                }
            }
        }
        used = l + 1;
    }
    m_pyramid.resize(used);

    // Levels bracketing [smin, smax], spaced by sqrt(2) from 0.5 px.
    std::vector<double> sigmas;
    double s = 0.5;
    while (s * kLevelRatio < smin) s *= kLevelRatio;
    for (; s < smax * kLevelRatio; s *= kLevelRatio) sigmas.push_back(s);
    if (sigmas.size() < 2) sigmas.push_back(s);
    m_levels.resize(sigmas.size());
    for (std::size_t i = 0; i < sigmas.size(); ++i) {
        m_levels[i].sigma = sigmas[i];
        build_level(m_levels[i], in);
    }

    tbb::parallel_for(0, H, [&](int v) {
        for (int u = 0; u < W; ++u) {
            const double sp = sigma.at(u, v);
            if (!(sp > 0.0)) continue;
            std::size_t i = 0;
            while (i + 2 < m_levels.size() && m_levels[i + 1].sigma < sp) ++i;
            const Level& a = m_levels[i];
            const Level& b = m_levels[i + 1];
            const double t = std::clamp((sp - a.sigma) / (b.sigma - a.sigma), 0.0, 1.0);
            float val[3];
            for (int c = 0; c < 3; ++c) {
                const float va = sample(a.rgbw, a.w, a.h, a.factor, c, u, v) /
                                 sample(a.rgbw, a.w, a.h, a.factor, 3, u, v);
                const float vb = sample(b.rgbw, b.w, b.h, b.factor, c, u, v) /
                                 sample(b.rgbw, b.w, b.h, b.factor, 3, u, v);
                val[c] = float((1.0 - t) * va + t * vb);
            }
            float* o = &out.at(u, v);
            o[0] = val[0];
            o[1] = val[1];
            o[2] = val[2];
        }
    });
}

}  // namespace deepsea
