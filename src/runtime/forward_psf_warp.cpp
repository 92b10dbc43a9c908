// The wide scales' blur at true angles off axis (ForwardPsfBlur::set_camera). A pinhole pixel
// theta off axis spans cos^2(theta) / fx radians radially and cos(theta) / fx across, so a
// Gaussian of a fixed width in pixels is too narrow there (by 1 / cos^2 = 1.62 radially at 38
// degrees): the table's angle psi lies at psi fx / cos^2 pixels. The grids of the wide scales
// hold the equidistant image instead, each pixel (u, v) at rho = fx atan(r / fx) along its
// radius, where a cell spans equal angles radially everywhere (across, theta / sin(theta) too
// many: 1.08 at 38 degrees). The level's weighted light goes in by splatting each pinhole cell
// bilinearly and dividing by the weights each cell received (a weighted mean, so a uniform
// surface stays uniform), and comes back out where the cascade reaches the finest pinhole grid
// below them: each of its cells samples the equidistant grid at its own place.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "deepsea/runtime/forward_psf_blur.h"
#include "equidistant.h"
#include "gaussian_planes.h"

namespace deepsea {

namespace {

/// The widest angle (rad) the equidistant grid maps back to the image plane: its cells beyond
/// (only on cameras wider than about 120 degrees) stand for points far beyond any frame.
constexpr double kMaxTheta = 1.45;
/// The narrowest warped scale's width (rad): narrower ones stay in the pinhole image, where
/// their width's error off axis is a small part of an angle the surface's light hardly
/// changes over, and warping the finer grids would cost about their size again.
constexpr double kWarpAngle = 1.0 / 40.0;

/// The scene continued beyond the frame at pixel (u, v): each side's falloff at the distance
/// beyond it, the product beyond a corner (as the blur takes its corners); 1 within.
void falloff_at(const EdgeFalloff* b, double u, double v, float f[3]) {
    f[0] = f[1] = f[2] = 1.0f;
    if (!b || b->samples() == 0) return;
    const int W = b->width, H = b->height;
    const int row = int(std::lround(std::clamp(v, 0.0, double(H - 1))));
    const int col = int(std::lround(std::clamp(u, 0.0, double(W - 1))));
    const auto side = [&](const std::vector<float>& s, int border, float beyond) {
        for (int c = 0; c < 3; ++c) f[c] *= b->at(s, border, c, beyond);
    };
    if (u < 0.0) side(b->left, row, float(-u));
    if (u > W - 1) side(b->right, row, float(u - (W - 1)));
    if (v < 0.0) side(b->top, col, float(-v));
    if (v > H - 1) side(b->bottom, col, float(v - (H - 1)));
}

/// Cell x's centre in pixels on a grid of factor f, and a pixel's place in cells.
double cell_centre(int x, int f) { return (x + 0.5) * f - 0.5; }
double cell_of(double u, int f) { return (u + 0.5) / f - 0.5; }

/// Bilinear taps at place x (clamped to the n >= 2 cells).
void taps(float x, int n, int& x0, float& t) {
    const float c = std::clamp(x, 0.0f, float(n - 1));
    x0 = std::min(int(c), n - 2);
    t = c - float(x0);
}

}  // namespace

void ForwardPsfBlur::set_camera(double fx, double fy, double cx, double cy) {
    m_cam[0] = fx;
    m_cam[1] = fy;
    m_cam[2] = cx;
    m_cam[3] = cy;
    m_width = m_height = 0;  // the grids and their maps are rebuilt by the next prepare()
}

void ForwardPsfBlur::to_equidistant(double u, double v, double& ue, double& ve) const {
    const double a = (u - m_cam[2]) / m_cam[0], b = (v - m_cam[3]) / m_cam[1];
    const double s = equidistant::atan_ratio(float(a * a + b * b));
    ue = m_cam[2] + s * (u - m_cam[2]);
    ve = m_cam[3] + s * (v - m_cam[3]);
}

void ForwardPsfBlur::from_equidistant(double ue, double ve, double& u, double& v) const {
    const double theta = std::hypot((ue - m_cam[2]) / m_cam[0], (ve - m_cam[3]) / m_cam[1]);
    const double s = theta > 1e-9 ? std::tan(std::min(theta, kMaxTheta)) / theta : 1.0;
    u = m_cam[2] + s * (ue - m_cam[2]);
    v = m_cam[3] + s * (ve - m_cam[3]);
}

void ForwardPsfBlur::build_warp() {
    m_warp = 0;
    m_warp_maps.clear();
    m_warp_x.clear();
    m_warp_y.clear();
    if (!(m_cam[0] > 0.0 && m_cam[1] > 0.0) || !m_psf.from_transport() || m_grids.empty()) return;
    // the finest warped grid: the first of factor >= 4 whose scales are kWarpAngle wide
    int F = 4;
    while (F < m_grids.back().factor && F < kWarpAngle * m_cam[0]) F *= 2;
    if (F > m_grids.back().factor) return;  // (frames under 32 px a side)
    m_warp = F;
    for (const Group& g : m_groups) {
        if (g.factor < F || m_warp_maps.count(g.factor)) continue;
        const int f = g.factor, w = g.w, h = g.h;
        WarpMap& m = m_warp_maps[f];
        m.ex.resize(std::size_t(w) * h);
        m.ey.resize(m.ex.size());
        std::vector<double> sum(m.ex.size(), 0.0);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                double ue = 0.0, ve = 0.0;
                to_equidistant(cell_centre(x, f), cell_centre(y, f), ue, ve);
                const std::size_t i = std::size_t(y) * w + x;
                m.ex[i] = float(cell_of(ue, f));
                m.ey[i] = float(cell_of(ve, f));
                int x0 = 0, y0 = 0;
                float tx = 0.0f, ty = 0.0f;
                taps(m.ex[i], w, x0, tx);
                taps(m.ey[i], h, y0, ty);
                const std::size_t o = std::size_t(y0) * w + x0;
                sum[o] += (1.0 - tx) * (1.0 - ty);
                sum[o + 1] += tx * (1.0 - ty);
                sum[o + w] += (1.0 - tx) * ty;
                sum[o + w + 1] += double(tx) * ty;
            }
        }
        m.norm.resize(sum.size());
        for (std::size_t i = 0; i < sum.size(); ++i) {
            // A cell whose centre lies beyond the frame is the scene continued (warp_level),
            // even where border cells splat into it: their mean would hold the border's light
            // unchanged a cell beyond it (measured: the frame's border pixels 4-7 % above a
            // frame a quarter wider).
            double u = 0.0, v = 0.0;
            from_equidistant(cell_centre(int(i) % w, f), cell_centre(int(i) / w, f), u, v);
            const bool beyond = u < -0.5 || u > m_width - 0.5 || v < -0.5 || v > m_height - 0.5;
            m.norm[i] = sum[i] > 1e-6 && !beyond ? float(1.0 / sum[i]) : 0.0f;
            if (m.norm[i] == 0.0f) m.margin.push_back(int(i));
        }
    }
    // the pinhole grid below the finest equidistant one: each cell's place there
    const Grid& G = grid_of(F / 2);
    m_warp_x.resize(std::size_t(G.w) * G.h);
    m_warp_y.resize(m_warp_x.size());
    for (int y = 0; y < G.h; ++y) {
        for (int x = 0; x < G.w; ++x) {
            double ue = 0.0, ve = 0.0;
            to_equidistant(cell_centre(x, G.factor), cell_centre(y, G.factor), ue, ve);
            m_warp_x[std::size_t(y) * G.w + x] = float(cell_of(ue, F));
            m_warp_y[std::size_t(y) * G.w + x] = float(cell_of(ve, F));
        }
    }
}

const float* ForwardPsfBlur::warp_level(const std::vector<float>& planes, int f, int w, int h,
                                        const EdgeFalloff* beyond) {
    const WarpMap& m = m_warp_maps.at(f);
    const std::size_t n = std::size_t(w) * h;
    m_eq.assign(3 * n, 0.0f);
    tbb::parallel_for(0, 3, [&](int c) {
        const float* __restrict P = planes.data() + c * n;
        float* __restrict Q = m_eq.data() + c * n;
        for (std::size_t i = 0; i < n; ++i) {
            int x0 = 0, y0 = 0;
            float tx = 0.0f, ty = 0.0f;
            taps(m.ex[i], w, x0, tx);
            taps(m.ey[i], h, y0, ty);
            const std::size_t o = std::size_t(y0) * w + x0;
            const float p = P[i], lo = p * (1.0f - ty), hi = p * ty;
            Q[o] += lo * (1.0f - tx);
            Q[o + 1] += lo * tx;
            Q[o + w] += hi * (1.0f - tx);
            Q[o + w + 1] += hi * tx;
        }
        for (std::size_t i = 0; i < n; ++i) Q[i] *= m.norm[i];
    });
    // cells beyond the frame: the nearest border cell continued, fading as `beyond` says
    for (const int i : m.margin) {
        double u = 0.0, v = 0.0;
        from_equidistant(cell_centre(i % w, f), cell_centre(i / w, f), u, v);
        const int x = int(std::lround(std::clamp(cell_of(u, f), 0.0, double(w - 1))));
        const int y = int(std::lround(std::clamp(cell_of(v, f), 0.0, double(h - 1))));
        float fall[3];
        falloff_at(beyond, u, v, fall);
        for (int c = 0; c < 3; ++c)
            m_eq[c * n + i] = planes[c * n + std::size_t(y) * w + x] * fall[c];
    }
    return m_eq.data();
}

int ForwardPsfBlur::fade_equidistant(const EdgeFalloff* beyond, int g) {
    if (g == m_faded_group) return m_faded_reach;
    const Group& G = m_groups[g];
    const int f = G.factor, w = G.w, h = G.h;
    const double sigma = m_psf.sigma_px(G.j1 - 1);  // the group's widest
    const int r = planes::radius(std::sqrt(std::max(sigma * sigma - G.spent, 0.09)) / f);
    m_faded_group = g;
    m_faded_reach = r;
    for (auto& v : m_fade) v.resize(std::size_t(3) * std::max(w, h) * r);
    // cell (x, y) of the grid, k cells beyond (x, y) along (dx, dy): its falloff over the cell's
    // (the border cells' own falloffs: left, right, top, bottom, 3 channels each)
    m_fade_border.resize(std::size_t(3) * 2 * (w + h));
    const auto own = [&](int x, int y, float* out) {
        double u = 0.0, v = 0.0;
        from_equidistant(cell_centre(x, f), cell_centre(y, f), u, v);
        falloff_at(beyond, u, v, out);
    };
    for (int y = 0; y < h; ++y) {
        own(0, y, &m_fade_border[3 * std::size_t(y)]);
        own(w - 1, y, &m_fade_border[3 * std::size_t(h + y)]);
    }
    for (int x = 0; x < w; ++x) {
        own(x, 0, &m_fade_border[3 * std::size_t(2 * h + x)]);
        own(x, h - 1, &m_fade_border[3 * std::size_t(2 * h + w + x)]);
    }
    const auto ratio = [&](int x, int y, int dx, int dy, int k, float out[3]) {
        const int side = dx < 0 ? 0 : dx > 0 ? 1 : dy < 0 ? 2 : 3;
        const int at = side < 2 ? side * h + y : 2 * h + (side - 2) * w + x;
        const float* a = &m_fade_border[3 * std::size_t(at)];
        double u = 0.0, v = 0.0;
        from_equidistant(cell_centre(x + k * dx, f), cell_centre(y + k * dy, f), u, v);
        falloff_at(beyond, u, v, out);
        for (int c = 0; c < 3; ++c) out[c] = a[c] > 1e-12f ? out[c] / a[c] : 1.0f;
    };
    float q[3];
    for (int k = 1; k <= r; ++k) {
        for (int y = 0; y < h; ++y) {
            ratio(0, y, -1, 0, k, q);
            for (int c = 0; c < 3; ++c) m_fade[0][(std::size_t(c) * h + y) * r + k - 1] = q[c];
            ratio(w - 1, y, 1, 0, k, q);
            for (int c = 0; c < 3; ++c) m_fade[1][(std::size_t(c) * h + y) * r + k - 1] = q[c];
        }
        for (int x = 0; x < w; ++x) {
            ratio(x, 0, 0, -1, k, q);
            for (int c = 0; c < 3; ++c) m_fade[2][(std::size_t(c) * r + k - 1) * w + x] = q[c];
            ratio(x, h - 1, 0, 1, k, q);
            for (int c = 0; c < 3; ++c) m_fade[3][(std::size_t(c) * r + k - 1) * w + x] = q[c];
        }
    }
    return r;
}

void ForwardPsfBlur::add_unwarped(Grid& G, const Grid& coarser) const {
    const int cw = coarser.w, ch = coarser.h;
    const std::size_t n = std::size_t(G.w) * G.h, cn = std::size_t(cw) * ch;
    const bool mom = !G.mom.empty() && !coarser.mom.empty();
    tbb::parallel_for(0, G.h, [&](int y) {
        for (int x = 0; x < G.w; ++x) {
            const std::size_t i = std::size_t(y) * G.w + x;
            int x0 = 0, y0 = 0;
            float tx = 0.0f, ty = 0.0f;
            taps(m_warp_x[i], cw, x0, tx);
            taps(m_warp_y[i], ch, y0, ty);
            const std::size_t o = std::size_t(y0) * cw + x0;
            const float w00 = (1.0f - tx) * (1.0f - ty), w01 = tx * (1.0f - ty);
            const float w10 = (1.0f - tx) * ty, w11 = tx * ty;
            for (int c = 0; c < 3; ++c) {
                const float* q = coarser.acc.data() + c * cn + o;
                G.acc[c * n + i] += w00 * q[0] + w01 * q[1] + w10 * q[cw] + w11 * q[cw + 1];
                if (!mom) continue;
                const float* p = coarser.mom.data() + c * cn + o;
                G.mom[c * n + i] += w00 * p[0] + w01 * p[1] + w10 * p[cw] + w11 * p[cw + 1];
            }
        }
    });
}

}  // namespace deepsea
