// The forward scatter's lean on surfaces tilted to the ray (optics/forward_lean.h): the
// symmetric blur's light plus l . grad M, M the blurred scales' light each times its sigma^2
// (ForwardPsfBlur::prepare keeps M beside the blurred light in every grid).

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "deepsea/runtime/forward_psf_blur.h"
#include "equidistant.h"

namespace deepsea {

namespace {

/// acc[i] += l . grad M at each cell of one w x h plane whose cells lie `step` px apart, l the
/// cell's lean (lean[2i], lean[2i + 1]); grad M by central differences, one-sided at the edges.
/// Held within the cell's own light: the kernel's factor 1 + l . (q - p) stays within [0, 2].
void lean_plane(int w, int h, float step, const float* mom, const float* lean, float* acc) {
    tbb::parallel_for(0, h, [&](int y) {
        const int y0 = std::max(y - 1, 0), y1 = std::min(y + 1, h - 1);
        const float sy = y1 > y0 ? 1.0f / (step * float(y1 - y0)) : 0.0f;
        const float* __restrict up = mom + std::size_t(y0) * w;
        const float* __restrict down = mom + std::size_t(y1) * w;
        const float* __restrict M = mom + std::size_t(y) * w;
        const float* __restrict l = lean + std::size_t(2) * y * w;
        float* __restrict a = acc + std::size_t(y) * w;
        auto at = [&](int x, float gx) {
            const float b = std::fabs(a[x]);
            const float d = l[2 * x] * gx + l[2 * x + 1] * (down[x] - up[x]) * sy;
            a[x] += std::min(std::max(d, -b), b);
        };
        if (w < 2) {
            if (w == 1) at(0, 0.0f);
            return;
        }
        at(0, (M[1] - M[0]) / step);
        const float sx = 0.5f / step;
#pragma omp simd
        for (int x = 1; x < w - 1; ++x) at(x, (M[x + 1] - M[x - 1]) * sx);
        at(w - 1, (M[w - 1] - M[w - 2]) / step);
    });
}

}  // namespace

void ForwardPsfBlur::add_level(std::size_t n, const float* blurred, float sigma2, float* acc,
                               float* mom) {
    for (std::size_t i = 0; i < n; ++i) {
        acc[i] += blurred[i];
        mom[i] += sigma2 * blurred[i];
    }
}

void ForwardPsfBlur::add_lean() {
    const int W = m_width, H = m_height;
    const Image& L = *m_lean;
    if (!m_full.empty()) {
        for (int c = 0; c < 3; ++c) {
            const std::size_t o = std::size_t(c) * W * H;
            lean_plane(W, H, 1.0f, m_full_mom.data() + o, L.data.data(), m_full.data() + o);
        }
    }
    if (m_grids.empty()) return;
    Grid& G = m_grids[0];
    m_cell_lean.resize(std::size_t(2) * G.w * G.h);
    // the factor-2 grid: each cell's lean the mean of its block's upper two pixels (the lean
    // changes slowly across a surface; the compositor computes only even rows' leans)
    tbb::parallel_for(0, G.h, [&](int y) {
        const float* __restrict r0 = L.row(2 * y);
        float* __restrict out = m_cell_lean.data() + std::size_t(2) * y * G.w;
        const int whole = W / 2;
#pragma omp simd
        for (int i = 0; i < 2 * whole; ++i) {
            const int x = i / 2, k = i % 2;  // cell x, component k
            out[i] = 0.5f * (r0[4 * x + k] + r0[4 * x + 2 + k]);
        }
        // (a block of one column at an odd frame's right edge: its own pixel)
        if (whole < G.w) {
            for (int k = 0; k < 2; ++k) out[2 * whole + k] = r0[4 * whole + k];
        }
        // At true angles the kernel's covariance in pixels is J J^T sigma^2 (equidistant.h),
        // taken at the middle of every `step` cells spanning at most 1/40 rad (it changes by
        // under 2 % over that at 38 degrees, where the lean is a few per cent of the light).
        if (m_warp == 0) return;
        thread_local std::vector<float> sxx, sxy, syy;
        sxx.resize(G.w);
        sxy.resize(G.w);
        syy.resize(G.w);
        const float ifx = float(1.0 / m_cam[0]), b = float((2 * y + 0.5 - m_cam[3]) / m_cam[1]);
        const float a0 = float((0.5 - m_cam[2]) / m_cam[0]);
        const int step = std::clamp(int(0.0125 * m_cam[0]), 1, 8);
        for (int x0 = 0; x0 < G.w; x0 += step) {
            float xx = 1.0f, xy = 0.0f, yy = 1.0f;
            equidistant::stretch(a0 + 2.0f * ifx * (float(x0) + 0.5f * float(step - 1)), b, xx, xy,
                                 yy);
            for (int x = x0; x < std::min(x0 + step, G.w); ++x)
                sxx[x] = xx, sxy[x] = xy, syy[x] = yy;
        }
#pragma omp simd
        for (int x = 0; x < G.w; ++x) {
            const float lu = out[2 * x], lv = out[2 * x + 1];
            out[2 * x] = sxx[x] * lu + sxy[x] * lv;
            out[2 * x + 1] = sxy[x] * lu + syy[x] * lv;
        }
    });
    for (int c = 0; c < 3; ++c) {
        const std::size_t o = std::size_t(c) * G.w * G.h;
        lean_plane(G.w, G.h, 2.0f, G.mom.data() + o, m_cell_lean.data(), G.acc.data() + o);
    }
}

}  // namespace deepsea
