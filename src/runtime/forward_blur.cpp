#include "deepsea/runtime/forward_blur.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "clones.h"
#include "deepsea/optics/forward.h"
#include "gaussian_planes.h"
#include "kernels.h"

namespace deepsea {

namespace {

constexpr double kLevelRatio = 1.4142135623730951;  // sqrt(2)
/// Weight of one blur level per pixel (sigma = scale * s, at most cap): a hat in sigma that is 1 at
/// the level's sigma s and 0 at its neighbours' (inv_lo, inv_hi: 1 / distance to them; 0 for an end
/// level, which keeps weight 1 beyond itself). Returns whether any pixel of the row uses the level.
/// The Jaffe-McGlamery blur G_(sigma(u)) * L_s, sigma(u) = fx k d2(u) (docs/model.md), is
/// sum_i h_i(u) (G_(s_i) * L_s)(u) with level i's hat
///   h_i(u) = max(0, 1 - |sigma_u - s_i| / |s_(i +- 1) - s_i|),  sigma_u = min(scale s(u), cap),
/// the neighbour on sigma_u's side, and h_i(u) = 0 where sigma_u <= 0: a pixel's h_i sum to 1.
DEEPSEA_CLONES
bool level_weights(int n, const float* __restrict sigma, float scale, float cap, float s,
                   float inv_lo, float inv_hi, float* __restrict w) {
    float any = 0.0f;
#pragma omp simd reduction(max : any)
    for (int u = 0; u < n; ++u) {
        const float raw = scale * sigma[u];
        const float sp = raw < cap ? raw : cap;
        const float d = sp < s ? (s - sp) * inv_lo : (sp - s) * inv_hi;
        const float h = std::max(1.0f - d, 0.0f);
        w[u] = sp > 0.0f ? h : 0.0f;
        any = std::max(any, w[u]);
    }
    return any > 0.0f;
}

/// One level's term of that sum: acc[u] += h_i(u) (G_(s_i) * L_s)(u).
DEEPSEA_CLONES
void add_weighted(int n, const float* __restrict w, const float* __restrict src,
                  float* __restrict acc) {
#pragma omp simd
    for (int u = 0; u < n; ++u) acc[u] += w[u] * src[u];
}

}  // namespace

void ForwardBlur::build_level(const Image& in, Level& L) {
    // Downsample while the reduced sigma stays >= 1 px, so the kernel keeps its shape.
    int lvl = 0;
    while (L.sigma / (1 << (lvl + 1)) >= 1.0 && lvl + 1 < int(m_pyramid.size())) ++lvl;
    const int f = 1 << lvl;
    L.factor = f;
    const planes::Source src =
        lvl == 0 ? planes::interleaved(in)
                 : planes::planar(m_pyramid[lvl].data.data(), m_pyramid[lvl].w, m_pyramid[lvl].h);
    L.blurred.w = src.w;
    L.blurred.h = src.h;
    L.blurred.data.resize(3 * std::size_t(src.w) * src.h);
    // Box downsampling by f and bilinear upsampling already spread the signal by about
    // (f^2 - 1)/12 + f^2/12 px^2; the level's Gaussian supplies the rest of the variance.
    const double spent = f > 1 ? (2.0 * f * f - 1.0) / 12.0 : 0.0;
    const double rest = std::sqrt(std::max(L.sigma * L.sigma - spent, 0.09)) / f;
    planes::blur_planes(src, L.blurred.data.data(), rest, m_kernel, m_norm_x, m_norm_y);
    // Horizontal bilinear taps, kept while the frame width and the factor stay the same.
    const int W = in.width;
    if (f > 1 && (L.taps_width != W || L.taps_factor != f)) {
        L.taps_width = W;
        L.taps_factor = f;
        L.x0.resize(W);
        L.x1.resize(W);
        L.ax.resize(W);
        for (int u = 0; u < W; ++u) {
            const float fx = (u + 0.5f) / f - 0.5f;
            const int x0 = std::clamp(int(std::floor(fx)), 0, src.w - 1);
            L.x0[u] = x0;
            L.x1[u] = std::min(x0 + 1, src.w - 1);
            L.ax[u] = std::clamp(fx - x0, 0.0f, 1.0f);
        }
    }
}

void ForwardBlur::prepare(const Image& in, const Image& s_img, float scale) {
    const int W = in.width, H = in.height;
    m_width = W;
    m_scale = scale;
    m_count = 0;
    // Range of sigma over blurred pixels: per row in parallel, then in row order.
    m_row_range.resize(H);
    tbb::parallel_for(0, H, [&](int v) {
        float lo = 1e30f, hi = 0.0f;
        const float* sr = s_img.row(v);
        for (int u = 0; u < W; ++u) {
            const float sp = scale * sr[u];
            if (sp > 0.0f) {
                lo = std::min(lo, sp);
                hi = std::max(hi, sp);
            }
        }
        m_row_range[v] = {lo, hi};
    });
    double smin = 1e30, smax = 0.0;
    for (const auto& [lo, hi] : m_row_range) {
        smin = std::min(smin, double(lo));
        smax = std::max(smax, double(hi));
    }
    if (smax <= 0.0) return;
    // Wider blurs are capped (as in the reference): the last level takes every pixel beyond.
    m_cap = float(max_forward_sigma_px(W, H));
    smax = std::min(smax, double(m_cap));
    smin = std::min(smin, smax);

    // Levels bracketing [smin, smax], spaced by sqrt(2) from 0.5 px.
    std::vector<double>& sigmas = m_sigmas;
    sigmas.clear();
    double s = 0.5;
    while (s * kLevelRatio < smin) s *= kLevelRatio;
    for (; s < smax * kLevelRatio; s *= kLevelRatio) sigmas.push_back(s);
    if (sigmas.size() < 2) sigmas.push_back(s);

    // Pyramid of 2x2 box averages (edge blocks average what they have), only as deep as the
    // widest level needs; level 0 is the input itself:
    //   A_l(x, y) = 1/4 sum_(a, b in {0, 1}) A_(l-1)(2x + a, 2y + b).
    int depth = 1;
    while ((2 << (depth - 1)) <= sigmas.back() && depth < 8 && std::min(W, H) >> depth >= 8) {
        ++depth;
    }
    m_pyramid.resize(depth);
    for (int l = 1; l < depth; ++l) {
        const Planes& prev = m_pyramid[l - 1];
        const planes::Source a =
            l == 1 ? planes::interleaved(in) : planes::planar(prev.data.data(), prev.w, prev.h);
        Planes& b = m_pyramid[l];
        b.w = (a.w + 1) / 2;
        b.h = (a.h + 1) / 2;
        b.data.resize(3 * std::size_t(b.w) * b.h);
        tbb::parallel_for(0, 3 * b.h, [&](int prow) {
            const int c = prow / b.h, y = prow % b.h;
            float* dst = b.plane(c) + std::size_t(y) * b.w;
            const int y0 = 2 * y, y1 = std::min(2 * y + 1, a.h - 1);
            for (int x = 0; x < b.w; ++x) {
                const int x0 = 2 * x, x1 = std::min(2 * x + 1, a.w - 1);
                // at an odd edge x1 == x0 (or y1 == y0): the block averages what it has
                dst[x] = 0.25f * (a(c, x0, y0) + a(c, x1, y0) + a(c, x0, y1) + a(c, x1, y1));
            }
        });
    }
    // Level objects (and their buffers) are kept across frames; only m_count are in use.
    m_count = int(sigmas.size());
    if (int(m_levels.size()) < m_count) m_levels.resize(m_count);
    for (int i = 0; i < m_count; ++i) {
        m_levels[i].sigma = sigmas[i];
        build_level(in, m_levels[i]);
    }
}

// Row v of sum_i h_i(u) (G_(s_i) * L_s)(u): each level's blurred planes, upsampled where the
// level was blurred on a coarser copy, weighted by its hat (level_weights, add_weighted).
void ForwardBlur::blend_row(int v, const float* s_row, float* out_rgb) const {
    const int W = m_width;
    const int n = m_count;
    thread_local std::vector<float> buf;
    buf.resize(5 * std::size_t(W));
    float* wgt = buf.data();
    float* acc = wgt + W;  // 3 planes
    float* tmp = acc + 3 * W;
    std::fill(acc, acc + 3 * W, 0.0f);
    for (int j = 0; j < n; ++j) {
        // Hat weight in sigma between the neighbouring levels; the end levels take all pixels
        // beyond them.
        const Level& L = m_levels[j];
        const float s = float(L.sigma);
        const float inv_lo = j > 0 ? float(1.0 / (L.sigma - m_levels[j - 1].sigma)) : 0.0f;
        const float inv_hi = j + 1 < n ? float(1.0 / (m_levels[j + 1].sigma - L.sigma)) : 0.0f;
        if (!level_weights(W, s_row, m_scale, m_cap, s, inv_lo, inv_hi, wgt)) continue;
        const Planes& P = L.blurred;
        for (int c = 0; c < 3; ++c) {
            const float* q = P.plane(c);
            if (L.factor == 1) {
                add_weighted(W, wgt, q + std::size_t(v) * P.w, acc + c * W);
                continue;
            }
            planes::add_upsampled_row(W, v, L.factor, q, P.w, P.h, L.x0.data(), L.x1.data(),
                                      L.ax.data(), wgt, tmp, acc + c * W);
        }
    }
    kernels::interleave(W, acc, out_rgb);
}

}  // namespace deepsea
