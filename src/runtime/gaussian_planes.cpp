#include "gaussian_planes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "clones.h"
#include "float4.h"

// (Float8 values live in registers inside the kernels: no call passes one, so GCC's note that
// AVX changes the ABI of such calls does not apply to their generic clones)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace deepsea::planes {

namespace {

/// Normalisation of a zero-padded 1-D convolution over n pixels, the taps that fall inside:
///   w[x] = 1 / sum_(k = max(-r, -x))^(min(r, n - 1 - x)) g_k.
void inside_weights(int n, const std::vector<float>& g, int r, std::vector<float>& w) {
    w.resize(n);
    for (int x = 0; x < n; ++x) {
        double s = 0.0;
        for (int k = std::max(-r, -x); k <= std::min(r, n - 1 - x); ++k) s += g[k + r];
        w[x] = float(1.0 / s);
    }
}

/// dst[x] = sum_(k < taps) gk[k] row(k)[x] for x < n: thirty-two outputs at a time (then
/// eight), their sums held in registers through every tap (the taps in the same order, each
/// added as before: the same bits as a pass over the row per tap, with a tap's weight loaded
/// once for them all); the last n % 8 tap by tap (a sum over taps per output would be
/// reassociated). Inlined into each pass, which keeps its own clones' rounding.
template <class Row>
[[gnu::always_inline]] inline void tap_sums(int n, int taps, const float* __restrict gk, Row row,
                                            float* __restrict dst) {
    int x = 0;
    for (; x + 32 <= n; x += 32) {
        Float8 s0 = {}, s1 = {}, s2 = {}, s3 = {};
        for (int k = 0; k < taps; ++k) {
            const float* p = row(k) + x;
            s0 += gk[k] * load8(p);
            s1 += gk[k] * load8(p + 8);
            s2 += gk[k] * load8(p + 16);
            s3 += gk[k] * load8(p + 24);
        }
        std::memcpy(dst + x, &s0, sizeof s0);
        std::memcpy(dst + x + 8, &s1, sizeof s1);
        std::memcpy(dst + x + 16, &s2, sizeof s2);
        std::memcpy(dst + x + 24, &s3, sizeof s3);
    }
    for (; x + 8 <= n; x += 8) {
        Float8 sum = {};
        for (int k = 0; k < taps; ++k) sum += gk[k] * load8(row(k) + x);
        std::memcpy(dst + x, &sum, sizeof sum);
    }
    for (int i = x; i < n; ++i) dst[i] = 0.0f;
    for (int k = 0; k < taps; ++k)
        for (int i = x; i < n; ++i) dst[i] += gk[k] * row(k)[i];
}

/// The horizontal pass of G_sigma, unnormalised, over a row padded with r zeros on each side:
///   dst[x] = sum_(k = -r)^(r) g_k src[x + k],  g_k = exp(-k^2 / (2 sigma^2)).
DEEPSEA_CLONES
void convolve_row(const float* __restrict padded, float* __restrict dst, int n,
                  const float* __restrict g, int r) {
    const auto row = [padded](int k) { return padded + k; };
    tap_sums(n, 2 * r + 1, g, row, dst);
}

/// dst[x] *= s[x].
DEEPSEA_CLONES_NO_FMA
void scale_row(int n, const float* __restrict s, float* __restrict dst) {
#pragma omp simd
    for (int x = 0; x < n; ++x) dst[x] *= s[x];
}

/// dst[x] += src[x].
DEEPSEA_CLONES_NO_FMA
void add_row(int n, const float* __restrict src, float* __restrict dst) {
#pragma omp simd
    for (int x = 0; x < n; ++x) dst[x] += src[x];
}

/// The most taps vertical_row holds in registers' reach (wider kernels: a pass per tap).
constexpr int kMaxTaps = 64;

/// Where the vertical pass is: row y of plane c, in a w x h image, radius r, the ring of rows.
struct RowAt {
    int w, h, r, ring, c, y;
    float ny;  ///< the row's normalisation
};

/// The vertical pass of output row y (blur_planes): dst[x] = sum_(k = k0)^(k1) g_(k + r) ny[y]
/// h_(y + k)[x], h the horizontal pass's rows in their ring slots (the nearest in-image row,
/// times the fade's factor beyond the image where given). AVX2 without fused multiply-adds: each
/// product and sum rounds as in the generic clone, so the bits do not depend on the processor.
DEEPSEA_CLONES_NO_FMA
void vertical_row(const RowAt& at, int k0, int k1, const float* __restrict g,
                  const float* __restrict rows, const Fade* fade, float* __restrict dst) {
    const int w = at.w, h = at.h, y = at.y;
    if (!fade && k1 - k0 < kMaxTaps) {
        // the sums in registers through every row (tap_sums, as convolve_row)
        const float* in[kMaxTaps];
        float gk[kMaxTaps];
        for (int k = k0; k <= k1; ++k) {
            in[k - k0] = rows + std::size_t(std::clamp(y + k, 0, h - 1) % at.ring) * w;
            gk[k - k0] = g[k + at.r] * at.ny;
        }
        const auto row = [&in](int k) { return in[k]; };
        tap_sums(w, k1 - k0 + 1, gk, row, dst);
        return;
    }
    std::fill(dst, dst + w, 0.0f);
    for (int k = k0; k <= k1; ++k) {
        const float gk = g[k + at.r] * at.ny;
        const int yk = std::clamp(y + k, 0, h - 1);
        const float* __restrict in = rows + std::size_t(yk % at.ring) * w;
        const int out = y + k < 0 ? -(y + k) : y + k - (h - 1);
        if (fade && out > 0) {
            const float* __restrict f = (y + k < 0 ? fade->top : fade->bottom) +
                                        (std::size_t(at.c) * fade->reach + out - 1) * w;
#pragma omp simd
            for (int x = 0; x < w; ++x) dst[x] += gk * in[x] * f[x];
            continue;
        }
#pragma omp simd
        for (int x = 0; x < w; ++x) dst[x] += gk * in[x];
    }
}

}  // namespace

Source interleaved(const Image& in) {
    return {in.data.data(), in.width, in.height, 1, 3, std::size_t(3) * in.width};
}

Source planar(const float* data, int w, int h) {
    return {data, w, h, std::size_t(w) * h, 1, std::size_t(w)};
}

// Per plane, the separable Gaussian normalised over in-image taps (the scene continues beyond
// the frame, docs/model.md):
//   (G_sigma * s)(x, y) = ny[y] sum_l g_l nx[x] sum_k g_k s(x + k, y + l),
// k and l over in-image pixels, nx and ny from inside_weights: a uniform image stays uniform.
// With Edge::Clamp, k and l run over the whole kernel, s(x + k, y + l) read at the nearest
// in-image pixel (times the fade's factor for its distance, where given), and
// nx = ny = 1 / sum_k g_k.
int radius(double sigma) { return std::max(1, int(std::ceil(3.0 * sigma))); }

void blur_planes(const Source& src, float* dst_planes, double sigma, std::vector<float>& g,
                 std::vector<float>& nx, std::vector<float>& ny, Store store, Edge edge,
                 const Fade* fade) {
    const int w = src.w, h = src.h;
    const int r = radius(sigma);
    g.resize(2 * r + 1);
    for (int i = -r; i <= r; ++i) g[i + r] = float(std::exp(-0.5 * i * i / (sigma * sigma)));
    const bool clamp = edge == Edge::Clamp;
    if (fade && !(clamp && fade->reach >= r)) fade = nullptr;
    if (clamp) {
        double total = 0.0;
        for (const float x : g) total += x;
        nx.assign(w, float(1.0 / total));
        ny.assign(h, float(1.0 / total));
    } else {
        inside_weights(w, g, r, nx);
        inside_weights(h, g, r, ny);
    }
    const std::size_t plane = std::size_t(w) * h;
    // Strips of rows, each through a ring of its 2r + 1 latest rows of the horizontal pass, so
    // that the horizontal pass is never written out and read back (a strip computes the r rows
    // on either side of it again). The sums are the two passes' own, in the same order.
    const int ring = 2 * r + 1, strip = std::max(32, 4 * r), strips = (h + strip - 1) / strip;
    tbb::parallel_for(0, 3 * strips, [&](int t) {
        const int c = t / strips, y0 = t % strips * strip, y1 = std::min(h, y0 + strip);
        thread_local std::vector<float> padded, rows, sum;
        padded.assign(w + 2 * r, 0.0f);
        rows.resize(std::size_t(ring) * w);
        sum.resize(w);
        for (int y = y0, next = std::max(0, y0 - r); y < y1; ++y) {
            // the horizontal pass up to row y + r, each row into its ring slot
            for (; next <= std::min(h - 1, y + r); ++next) {
                const float* in = src.at(c, next);
                for (int x = 0; x < w; ++x) padded[r + x] = in[x * src.pixel];
                if (fade) {
                    const float* fl = fade->left + (std::size_t(c) * h + next) * fade->reach;
                    const float* fr = fade->right + (std::size_t(c) * h + next) * fade->reach;
                    for (int k = 1; k <= r; ++k) {
                        padded[r - k] = padded[r] * fl[k - 1];
                        padded[r + w - 1 + k] = padded[r + w - 1] * fr[k - 1];
                    }
                } else if (clamp) {
                    std::fill(padded.begin(), padded.begin() + r, padded[r]);
                    std::fill(padded.begin() + r + w, padded.end(), padded[r + w - 1]);
                }
                float* dst = rows.data() + std::size_t(next % ring) * w;
                convolve_row(padded.data(), dst, w, g.data(), r);
                scale_row(w, nx.data(), dst);
            }
            float* out = dst_planes + c * plane + std::size_t(y) * w;
            float* dst = store == Store::Add ? sum.data() : out;
            const int k0 = clamp ? -r : std::max(-r, -y), k1 = clamp ? r : std::min(r, h - 1 - y);
            vertical_row({w, h, r, ring, c, y, ny[y]}, k0, k1, g.data(), rows.data(), fade, dst);
            if (store == Store::Add) add_row(w, dst, out);
        }
    });
}

DEEPSEA_CLONES_NO_FMA
void add_planes(std::size_t n, const float* __restrict src, float* __restrict dst) {
#pragma omp simd
    for (std::size_t i = 0; i < n; ++i) dst[i] += src[i];
}

/// dst[x] = a[x] + t (b[x] - a[x]): a row between two rows.
DEEPSEA_CLONES
void lerp_rows(int n, const float* __restrict a, const float* __restrict b, float t,
               float* __restrict dst) {
#pragma omp simd
    for (int x = 0; x < n; ++x) dst[x] = a[x] + t * (b[x] - a[x]);
}

/// acc[u] += w[u] (q[x0_u] + ax_u (q[x1_u] - q[x0_u])): a weighted, horizontally interpolated
/// sample of the coarse row q.
DEEPSEA_CLONES
void add_upsampled(int n, const float* __restrict w, const float* __restrict row,
                   const int* __restrict x0, const int* __restrict x1, const float* __restrict ax,
                   float* __restrict acc) {
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float a = row[x0[u]], b = row[x1[u]];
        acc[u] += w[u] * (a + ax[u] * (b - a));
    }
}

// Bilinear in both directions: the coarse rows y0, y1 around p_y = (v + 1/2) / factor - 1/2
// blended (lerp_rows), then sampled per column (add_upsampled).
void add_upsampled_row(int n, int v, int factor, const float* q, int w_lo, int h_lo, const int* x0,
                       const int* x1, const float* ax, const float* w, float* tmp, float* acc) {
    const float fy = (v + 0.5f) / factor - 0.5f;
    const int y0 = std::clamp(int(std::floor(fy)), 0, h_lo - 1);
    const int y1 = std::min(y0 + 1, h_lo - 1);
    const float ay = std::clamp(fy - y0, 0.0f, 1.0f);
    lerp_rows(w_lo, q + std::size_t(y0) * w_lo, q + std::size_t(y1) * w_lo, ay, tmp);
    add_upsampled(n, w, tmp, x0, x1, ax, acc);
}

}  // namespace deepsea::planes
