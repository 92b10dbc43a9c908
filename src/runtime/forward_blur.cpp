#include "deepsea/runtime/forward_blur.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "clones.h"

namespace deepsea {

namespace {

constexpr double kLevelRatio = 1.4142135623730951;  // sqrt(2)

/// Normalisation of a zero-padded 1-D convolution: the sum of the taps that fall inside.
std::vector<float> inside_weights(int n, const std::vector<float>& g, int r) {
    std::vector<float> w(n);
    for (int x = 0; x < n; ++x) {
        double s = 0.0;
        for (int k = std::max(-r, -x); k <= std::min(r, n - 1 - x); ++k) s += g[k + r];
        w[x] = float(1.0 / s);
    }
    return w;
}

/// dst[x] = sum_k g[k] src[x + k] over a row padded with r zeros on each side.
DEEPSEA_CLONES
void convolve_row(const float* __restrict padded, float* __restrict dst, int n,
                  const float* __restrict g, int r) {
    for (int x = 0; x < n; ++x) dst[x] = 0.0f;
    for (int k = 0; k <= 2 * r; ++k) {
        const float gk = g[k];
        const float* s = padded + k;
#pragma omp simd
        for (int x = 0; x < n; ++x) dst[x] += gk * s[x];
    }
}

/// Separable normalised Gaussian of `sigma` (pixels of this resolution) of 3 planes, src to dst.
void blur_planes(const float* src_planes, float* data, int w, int h, double sigma,
                 std::vector<float>& tmp) {
    const int r = std::max(1, int(std::ceil(3.0 * sigma)));
    std::vector<float> g(2 * r + 1);
    for (int i = -r; i <= r; ++i) g[i + r] = float(std::exp(-0.5 * i * i / (sigma * sigma)));
    const std::vector<float> nx = inside_weights(w, g, r), ny = inside_weights(h, g, r);
    const std::size_t plane = std::size_t(w) * h;
    tmp.resize(3 * plane);
    tbb::parallel_for(0, 3 * h, [&](int row) {
        thread_local std::vector<float> padded;
        padded.assign(w + 2 * r, 0.0f);
        const float* src = src_planes + std::size_t(row) * w;
        std::copy(src, src + w, padded.begin() + r);
        float* dst = tmp.data() + std::size_t(row) * w;
        convolve_row(padded.data(), dst, w, g.data(), r);
        for (int x = 0; x < w; ++x) dst[x] *= nx[x];
    });
    tbb::parallel_for(0, 3 * h, [&](int prow) {
        const int p = prow / h, y = prow % h;
        float* dst = data + p * plane + std::size_t(y) * w;
        std::fill(dst, dst + w, 0.0f);
        const int k0 = std::max(-r, -y), k1 = std::min(r, h - 1 - y);
        for (int k = k0; k <= k1; ++k) {
            const float gk = g[k + r] * ny[y];
            const float* src = tmp.data() + p * plane + std::size_t(y + k) * w;
#pragma omp simd
            for (int x = 0; x < w; ++x) dst[x] += gk * src[x];
        }
    });
}

/// Weight of one blur level per pixel: a hat in sigma that is 1 at the level's sigma s and 0 at
/// its neighbours' (inv_lo, inv_hi: 1 / distance to them; 0 for an end level, which keeps
/// weight 1 beyond itself). Returns whether any pixel of the row uses the level.
DEEPSEA_CLONES
bool level_weights(int n, const float* __restrict sigma, float s, float inv_lo, float inv_hi,
                   float* __restrict w) {
    float any = 0.0f;
#pragma omp simd reduction(max : any)
    for (int u = 0; u < n; ++u) {
        const float sp = sigma[u];
        const float d = sp < s ? (s - sp) * inv_lo : (sp - s) * inv_hi;
        const float h = std::max(1.0f - d, 0.0f);
        w[u] = sp > 0.0f ? h : 0.0f;
        any = std::max(any, w[u]);
    }
    return any > 0.0f;
}

DEEPSEA_CLONES
void add_weighted(int n, const float* __restrict w, const float* __restrict src,
                  float* __restrict acc) {
#pragma omp simd
    for (int u = 0; u < n; ++u) acc[u] += w[u] * src[u];
}

DEEPSEA_CLONES
void lerp_rows(int n, const float* __restrict a, const float* __restrict b, float t,
               float* __restrict dst) {
#pragma omp simd
    for (int x = 0; x < n; ++x) dst[x] = a[x] + t * (b[x] - a[x]);
}

/// acc[u] += w[u] * (bilinear sample of the low-resolution row at x0[u] .. x1[u]).
DEEPSEA_CLONES
void add_upsampled(int n, const float* __restrict w, const float* __restrict row,
                   const int* __restrict x0, const int* __restrict x1,
                   const float* __restrict ax, float* __restrict acc) {
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float a = row[x0[u]], b = row[x1[u]];
        acc[u] += w[u] * (a + ax[u] * (b - a));
    }
}

DEEPSEA_CLONES
void interleave(int n, const float* __restrict planes, float* __restrict rgb) {
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        rgb[3 * u] = planes[u];
        rgb[3 * u + 1] = planes[n + u];
        rgb[3 * u + 2] = planes[2 * n + u];
    }
}

}  // namespace

void ForwardBlur::build_level(Level& L) {
    // Downsample while the reduced sigma stays >= 1 px, so the kernel keeps its shape.
    int lvl = 0;
    while (L.sigma / (1 << (lvl + 1)) >= 1.0 && lvl + 1 < int(m_pyramid.size())) ++lvl;
    const int f = 1 << lvl;
    L.factor = f;
    const Planes& src = m_pyramid[lvl];
    L.blurred.w = src.w;
    L.blurred.h = src.h;
    L.blurred.data.resize(src.data.size());
    // Box downsampling by f and bilinear upsampling already spread the signal by about
    // (f^2 - 1)/12 + f^2/12 px^2; the level's Gaussian supplies the rest of the variance.
    const double spent = f > 1 ? (2.0 * f * f - 1.0) / 12.0 : 0.0;
    const double rest = std::sqrt(std::max(L.sigma * L.sigma - spent, 0.09)) / f;
    blur_planes(src.data.data(), L.blurred.data.data(), src.w, src.h, rest, m_tmp);
}

void ForwardBlur::apply(const Image& in, const Image& sigma, Image& out) {
    const int W = in.width, H = in.height;
    if (out.width != W || out.height != H || out.channels != 3) out = Image(W, H, 3);
    // Range of sigma over surface pixels: per row in parallel, then in row order.
    m_row_range.resize(H);
    tbb::parallel_for(0, H, [&](int v) {
        float lo = 1e30f, hi = 0.0f;
        const float* sr = sigma.row(v);
        for (int u = 0; u < W; ++u) {
            if (sr[u] > 0.0f) {
                lo = std::min(lo, sr[u]);
                hi = std::max(hi, sr[u]);
            }
        }
        m_row_range[v] = {lo, hi};
    });
    double smin = 1e30, smax = 0.0;
    for (const auto& [lo, hi] : m_row_range) {
        smin = std::min(smin, double(lo));
        smax = std::max(smax, double(hi));
    }
    if (smax <= 0.0) {
        std::fill(out.data.begin(), out.data.end(), 0.0f);
        return;
    }

    // Levels bracketing [smin, smax], spaced by sqrt(2) from 0.5 px.
    std::vector<double> sigmas;
    double s = 0.5;
    while (s * kLevelRatio < smin) s *= kLevelRatio;
    for (; s < smax * kLevelRatio; s *= kLevelRatio) sigmas.push_back(s);
    if (sigmas.size() < 2) sigmas.push_back(s);

    // Pyramid: planar input, then 2x2 box averages (edge blocks average what they have),
    // only as deep as the widest level needs.
    int depth = 1;
    while ((2 << (depth - 1)) <= sigmas.back() && depth < 8 &&
           std::min(W, H) >> depth >= 8) {
        ++depth;
    }
    m_pyramid.resize(depth);
    Planes& p0 = m_pyramid[0];
    p0.w = W;
    p0.h = H;
    p0.data.resize(3 * std::size_t(W) * H);
    tbb::parallel_for(0, H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c) p0.plane(c)[std::size_t(y) * W + x] = in.at(x, y, c);
        }
    });
    for (int l = 1; l < depth; ++l) {
        const Planes& a = m_pyramid[l - 1];
        Planes& b = m_pyramid[l];
        b.w = (a.w + 1) / 2;
        b.h = (a.h + 1) / 2;
        b.data.resize(3 * std::size_t(b.w) * b.h);
        tbb::parallel_for(0, 3 * b.h, [&](int prow) {
            const int c = prow / b.h, y = prow % b.h;
            const float* src = a.plane(c);
            float* dst = b.plane(c) + std::size_t(y) * b.w;
            const int y0 = 2 * y, y1 = std::min(2 * y + 1, a.h - 1);
            for (int x = 0; x < b.w; ++x) {
                const int x0 = 2 * x, x1 = std::min(2 * x + 1, a.w - 1);
                // at an odd edge x1 == x0 (or y1 == y0): the block averages what it has
                dst[x] = 0.25f * (src[y0 * a.w + x0] + src[y0 * a.w + x1] + src[y1 * a.w + x0] +
                                  src[y1 * a.w + x1]);
            }
        });
    }
    m_levels.resize(sigmas.size());
    for (std::size_t i = 0; i < sigmas.size(); ++i) {
        m_levels[i].sigma = sigmas[i];
        build_level(m_levels[i]);
    }

    blend(sigma, out);
}

void ForwardBlur::blend(const Image& sigma, Image& out) {
    const int W = sigma.width, H = sigma.height;
    const int n = int(m_levels.size());
    // Horizontal bilinear taps per downsampling factor, once per frame size.
    for (Level& L : m_levels) {
        const int f = L.factor, w = L.blurred.w;
        if (f == 1 || (L.taps_width == W && L.taps_factor == f)) continue;
        L.taps_width = W;
        L.taps_factor = f;
        L.x0.resize(W);
        L.x1.resize(W);
        L.ax.resize(W);
        for (int u = 0; u < W; ++u) {
            const float fx = (u + 0.5f) / f - 0.5f;
            const int x0 = std::clamp(int(std::floor(fx)), 0, w - 1);
            L.x0[u] = x0;
            L.x1[u] = std::min(x0 + 1, w - 1);
            L.ax[u] = std::clamp(fx - x0, 0.0f, 1.0f);
        }
    }
    tbb::parallel_for(0, H, [&](int v) {
        thread_local std::vector<float> buf;
        buf.resize(5 * std::size_t(W));
        float* wgt = buf.data();
        float* acc = wgt + W;  // 3 planes
        float* tmp = acc + 3 * W;
        std::fill(acc, acc + 3 * W, 0.0f);
        const float* sr = sigma.row(v);
        for (int j = 0; j < n; ++j) {
            // Hat weight in sigma between the neighbouring levels; the end levels take all
            // pixels beyond them. Pixels without a surface (sigma <= 0) get nothing.
            const float s = float(m_levels[j].sigma);
            const float lo = j > 0 ? float(m_levels[j - 1].sigma) : -1e30f;
            const float hi = j + 1 < n ? float(m_levels[j + 1].sigma) : 1e30f;
            const float inv_lo = j > 0 ? 1.0f / (s - lo) : 0.0f;
            const float inv_hi = j + 1 < n ? 1.0f / (hi - s) : 0.0f;
            if (!level_weights(W, sr, s, inv_lo, inv_hi, wgt)) continue;
            const Level& L = m_levels[j];
            const Planes& P = L.blurred;
            for (int c = 0; c < 3; ++c) {
                const float* q = P.plane(c);
                if (L.factor == 1) {
                    add_weighted(W, wgt, q + std::size_t(v) * P.w, acc + c * W);
                    continue;
                }
                const float fy = (v + 0.5f) / L.factor - 0.5f;
                const int y0 = std::clamp(int(std::floor(fy)), 0, P.h - 1);
                const int y1 = std::min(y0 + 1, P.h - 1);
                const float ay = std::clamp(fy - y0, 0.0f, 1.0f);
                lerp_rows(P.w, q + std::size_t(y0) * P.w, q + std::size_t(y1) * P.w, ay, tmp);
                add_upsampled(W, wgt, tmp, L.x0.data(), L.x1.data(), L.ax.data(), acc + c * W);
            }
        }
        float* o = out.row(v);
        interleave(W, acc, o);
    });
}

}  // namespace deepsea
