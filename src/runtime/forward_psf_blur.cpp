#include "deepsea/runtime/forward_psf_blur.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

#include "clones.h"
#include "gaussian_planes.h"
#include "kernels.h"

namespace deepsea {

namespace {

constexpr int kTableBins = 1024;

/// Downsampling factor for a Gaussian of sigma pixels: the largest power of two that leaves
/// sigma at least one pixel of the smaller image, keeps that image at least 8 pixels high and
/// wide, and is at most 128.
int level_factor(double sigma, int width, int height) {
    int f = 1;
    while (2 * f <= sigma && f < 128 && std::min(width, height) / (2 * f) >= 8) f *= 2;
    return f;
}

/// x[u] = (the table's value at distance index idx[u] + frac[u]) * L[u]; 0 where idx < 0.
DEEPSEA_CLONES
void weigh_row(int n, const int* __restrict idx, const float* __restrict frac,
               const float* __restrict tab, const float* __restrict L, float* __restrict x) {
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const int i = idx[u] < 0 ? 0 : idx[u];
        const float a = tab[i], b = tab[i + 1];
        const float w = a + frac[u] * (b - a);
        x[u] = idx[u] < 0 ? 0.0f : w * L[u];
    }
}

}  // namespace

void ForwardPsfBlur::build_table(double d_max) {
    const int S = m_psf.scales();
    m_bins = kTableBins;
    m_step = d_max / m_bins;
    const std::size_t bins = std::size_t(m_bins) + 1;
    m_table.assign(bins * S * 3, 0.0f);
    tbb::parallel_for(0, m_bins + 1, [&](int i) {
        for (int j = 0; j < S; ++j) {
            const Rgb w = m_psf.weight(j, i * m_step);
            for (int c = 0; c < 3; ++c) m_table[(std::size_t(j) * 3 + c) * bins + i] = float(w[c]);
        }
    });
}

void ForwardPsfBlur::prepare(const Image& surface, const Image& d2) {
    const int W = surface.width, H = surface.height, S = m_psf.scales();
    // The table spans the frame's farthest surface (rebuilt only when a frame reaches beyond
    // it) but no farther than where every weight is below 1e-17 of a surface's radiance.
    const double d_frame = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, H), 0.0,
        [&](const tbb::blocked_range<int>& r, double m) {
            for (int v = r.begin(); v < r.end(); ++v) {
                const float* d = d2.row(v);
                for (int u = 0; u < W; ++u) m = std::max(m, double(d[u]));
            }
            return m;
        },
        [](double a, double b) { return std::max(a, b); });
    const double d_limit = m_psf.negligible_beyond();
    const double d_max = std::min(d_frame, d_limit);
    if (m_table.empty() || d_max > m_bins * m_step) build_table(std::max(d_max * 1.25, 1.0));
    const double range = m_bins * m_step;

    if (m_width != W || m_height != H) {
        m_width = W;
        m_height = H;
        m_sharp.assign(std::size_t(3) * W * H, 0.0f);
        m_levels.assign(S - 1, Level{});
        for (int j = 1; j < S; ++j) {
            Level& L = m_levels[j - 1];
            L.factor = level_factor(m_psf.sigma_px(j), W, H);
            L.w = (W + L.factor - 1) / L.factor;
            L.h = (H + L.factor - 1) / L.factor;
            if (L.factor > 1) L.partial.assign(std::size_t(3) * L.w * H, 0.0f);
            L.planes.assign(std::size_t(3) * L.w * L.h, 0.0f);
            L.blurred.assign(L.planes.size(), 0.0f);
            L.x0.resize(W);
            L.x1.resize(W);
            L.ax.resize(W);
            for (int u = 0; u < W; ++u) {
                const float fx = (u + 0.5f) / L.factor - 0.5f;
                const int x0 = std::clamp(int(std::floor(fx)), 0, L.w - 1);
                L.x0[u] = x0;
                L.x1[u] = std::min(x0 + 1, L.w - 1);
                L.ax[u] = std::clamp(fx - x0, 0.0f, 1.0f);
            }
        }
    }

    // Weigh: each pixel's radiance times its scales' shares at its distance; full-resolution
    // scales go straight into their planes, wider ones into per-row block sums.
    const float inv_step = float(1.0 / m_step);
    const int bins = m_bins + 1;
    tbb::parallel_for(0, H, [&](int v) {
        thread_local std::vector<int> idx;
        thread_local std::vector<float> frac, L, x;
        idx.resize(W);
        frac.resize(W);
        L.resize(3 * std::size_t(W));
        x.resize(3 * std::size_t(W));
        const float* dr = d2.row(v);
        const float* Ls = surface.row(v);
        for (int u = 0; u < W; ++u) {
            const float d = dr[u];
            const bool on = d > 0.0f && d < range;
            const float t = on ? d * inv_step : 0.0f;
            const int i = std::min(int(t), m_bins - 1);
            idx[u] = on ? i : -1;
            frac[u] = t - float(i);
            for (int c = 0; c < 3; ++c) L[std::size_t(c) * W + u] = Ls[3 * u + c];
        }
        // x = W_j(d) L_s, planar, for one scale at a time (the table is [scale][channel][d])
        const auto weigh = [&](int j) {
            for (int c = 0; c < 3; ++c) {
                weigh_row(W, idx.data(), frac.data(),
                          m_table.data() + (std::size_t(j) * 3 + c) * bins,
                          L.data() + std::size_t(c) * W, x.data() + std::size_t(c) * W);
            }
        };
        weigh(0);
        float* sharp = m_sharp.data() + std::size_t(3) * W * v;
        for (int u = 0; u < W; ++u) {
            for (int c = 0; c < 3; ++c) sharp[3 * u + c] = x[std::size_t(c) * W + u];
        }
        for (int j = 1; j < S; ++j) {
            Level& Lv = m_levels[j - 1];
            weigh(j);
            if (Lv.factor == 1) {
                for (int c = 0; c < 3; ++c) {
                    std::copy(x.begin() + std::size_t(c) * W, x.begin() + std::size_t(c + 1) * W,
                              Lv.planes.begin() + (std::size_t(c) * H + v) * W);
                }
                continue;
            }
            float* p = Lv.partial.data() + std::size_t(3) * Lv.w * v;
            for (int c = 0; c < 3; ++c) {
                const float* xc = x.data() + std::size_t(c) * W;
                for (int bx = 0; bx < Lv.w; ++bx) {
                    const int u0 = bx * Lv.factor, u1 = std::min(u0 + Lv.factor, W);
                    float sum = 0.0f;
                    for (int u = u0; u < u1; ++u) sum += xc[u];
                    p[3 * bx + c] = sum;
                }
            }
        }
    });

    // Block sums to block means (edge blocks average what they have), then each level's blur:
    // box downsampling and bilinear upsampling by f spread about (2 f^2 - 1) / 12 px^2
    // already; the Gaussian supplies the rest of the scale's variance.
    for (int j = 1; j < S; ++j) {
        Level& L = m_levels[j - 1];
        const int f = L.factor;
        if (f > 1) {
            tbb::parallel_for(0, 3 * L.h, [&](int prow) {
                const int c = prow / L.h, y = prow % L.h;
                const int v0 = y * f, v1 = std::min(v0 + f, H);
                float* dst = L.planes.data() + (std::size_t(c) * L.h + y) * L.w;
                for (int x = 0; x < L.w; ++x) {
                    float sum = 0.0f;
                    for (int v = v0; v < v1; ++v)
                        sum += L.partial[(std::size_t(v) * L.w + x) * 3 + c];
                    const int cols = std::min(f, W - x * f);
                    dst[x] = sum / float(cols * (v1 - v0));
                }
            });
        }
        const double sigma = m_psf.sigma_px(j);
        const double spent = f > 1 ? (2.0 * f * f - 1.0) / 12.0 : 0.0;
        const double rest = std::sqrt(std::max(sigma * sigma - spent, 0.09)) / f;
        planes::blur_planes(planes::planar(L.planes.data(), L.w, L.h), L.blurred.data(), rest,
                            m_kernel, m_norm_x, m_norm_y, m_tmp);
    }
}

void ForwardPsfBlur::row(int v, float* out_rgb) const {
    const int W = m_width;
    thread_local std::vector<float> buf;
    buf.resize(std::size_t(6) * W);
    float* acc = buf.data();  // 3 planes
    float* tmp = acc + 3 * W;
    float* ones = tmp + 2 * W;
    std::fill(acc, acc + 3 * W, 0.0f);
    std::fill(ones, ones + W, 1.0f);
    for (const Level& L : m_levels) {
        for (int c = 0; c < 3; ++c) {
            const float* q = L.blurred.data() + std::size_t(c) * L.w * L.h;
            if (L.factor == 1) {
                const float* src = q + std::size_t(v) * W;
                for (int u = 0; u < W; ++u) acc[c * W + u] += src[u];
                continue;
            }
            planes::add_upsampled_row(W, v, L.factor, q, L.w, L.h, L.x0.data(), L.x1.data(),
                                      L.ax.data(), ones, tmp, acc + c * W);
        }
    }
    kernels::interleave(W, acc, out_rgb);
    const float* sharp = m_sharp.data() + std::size_t(3) * W * v;
    for (int i = 0; i < 3 * W; ++i) out_rgb[i] += sharp[i];
}

}  // namespace deepsea
