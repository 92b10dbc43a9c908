#include "deepsea/runtime/port_rays.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "deepsea/core/error.h"
#include "deepsea/optics/normals.h"

namespace deepsea {

PortRays::PortRays(const Port& port, const Camera& camera)
    : m_port(port),
      m_camera(camera),
      m_rays(std::size_t(camera.width) * camera.height),
      m_factor(camera.width, camera.height, 3) {
    check_port_sees_input(port, camera);
    tbb::parallel_for(0, camera.height, [&](int v) {
        for (int u = 0; u < camera.width; ++u) {
            const PortRay r = trace_port(port, camera, u, v);
            Ray& f = m_rays[std::size_t(v) * camera.width + u];
            const Vec3& d = r.direction[1];
            const RayProjection p = r.valid() ? project_ray(camera, r.origin, d) : RayProjection{};
            const PortMarch<double> m = port_march(camera, p);
            f = {float(r.origin.x),
                 float(r.origin.y),
                 float(r.origin.z),
                 float(d.x),
                 float(d.y),
                 float(d.z),
                 float(p.u_inf - u),
                 float(p.v_inf - v),
                 float(p.du),
                 float(p.dv),
                 p.forward ? float(std::min(p.s_origin, 1e30)) : 0.0f,
                 float(m.s_lo),
                 float(m.s_hi),
                 float(m.rate)};
            const Rgb k = port_radiance_factor(port, r);
            for (int c = 0; c < 3; ++c) m_factor.at(u, v, c) = float(k[c]);
        }
    });
    m_water_fx = port_water_fx(port, camera);
    const std::size_t n = m_rays.size();
    constexpr int F = kMarchRowFields;
    m_march_soa.resize(F * n);
    tbb::parallel_for(0, camera.height, [&](int v) {
        for (int u = 0; u < camera.width; ++u) {
            const PortMarch<float> m = march(u, v);
            const Ray& r = ray(u, v);
            const float fields[F] = {m.u_inf, m.v_inf, m.du, m.dv, m.s_origin,
                                     m.s_lo,  m.s_hi,  r.oz, r.dz};
            const std::size_t i = std::size_t(v) * camera.width + u;
            for (int f = 0; f < F; ++f) m_march_soa[f * n + i] = fields[f];
        }
    });
    const float* f = m_march_soa.data();
    const int W = camera.width, H = camera.height;
    m_row_hi.assign(H, std::numeric_limits<float>::infinity());
    m_row_lo_zero.assign(H, 1);
    m_zero_row.assign(W, 0.0f);
    m_inf_row.assign(W, std::numeric_limits<float>::infinity());
    for (int v = 0; v < H; ++v) {
        const MarchRow m = march_row(v);
        float hi = m_row_hi[v];
        for (int u = 0; u < W; ++u) {
            // (written so that a NaN takes hi's place: no row with one uses the constants)
            hi = !(m.s_origin[u] >= hi) ? m.s_origin[u] : hi;
            hi = !(m.s_hi[u] >= hi) ? m.s_hi[u] : hi;
            if (!(m.s_lo[u] == 0.0f && !std::signbit(m.s_lo[u]))) m_row_lo_zero[v] = 0;
        }
        m_row_hi[v] = hi;
    }
    const float* oz = march_row(0).oz;
    bool same_oz = true;
    for (std::size_t i = 1; i < n && same_oz; ++i)
        same_oz = std::memcmp(oz + i, oz, sizeof(float)) == 0;
    if (same_oz) m_oz_row.assign(W, oz[0]);
    m_u_lo = m_v_lo = std::numeric_limits<double>::infinity();
    m_u_hi = m_v_hi = -m_u_lo;
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) {
        const double u = f[i], v = f[n + i], du = std::fabs(f[2 * n + i]),
                     dv = std::fabs(f[3 * n + i]);
        finite = finite && std::isfinite(u) && std::isfinite(v) && std::isfinite(du) &&
                 std::isfinite(dv);
        m_u_lo = std::min(m_u_lo, u);
        m_u_hi = std::max(m_u_hi, u);
        m_v_lo = std::min(m_v_lo, v);
        m_v_hi = std::max(m_v_hi, v);
        m_du = std::max(m_du, du);
        m_dv = std::max(m_dv, dv);
    }
    if (!finite) m_u_lo = -std::numeric_limits<double>::infinity();  // reach: the whole image
}

PortRays::MarchRow PortRays::march_row(int v, float s_near) const {
    MarchRow m = march_row(v);
    if (m_row_lo_zero[v] && m_row_hi[v] > 0.0f && s_near <= m_row_hi[v]) {
        m.s_lo = m_zero_row.data();
        m.s_origin = m.s_hi = m_inf_row.data();
    }
    if (!m_oz_row.empty()) m.oz = m_oz_row.data();
    return m;
}

PortRays::PixelBox PortRays::reach(double s_max) const {
    const int W = m_camera.width, H = m_camera.height;
    const double s = 1.01 * std::max(s_max, 0.0), margin = 3.0;
    const double x0 = m_u_lo - m_du * s - margin, x1 = m_u_hi + m_du * s + margin;
    const double y0 = m_v_lo - m_dv * s - margin, y1 = m_v_hi + m_dv * s + margin;
    if (!(std::isfinite(x0) && std::isfinite(x1) && std::isfinite(y0) && std::isfinite(y1)))
        return {0, W - 1, 0, H - 1};
    const auto clamp = [](double x, int n) { return int(std::clamp(std::floor(x), 0.0, n - 1.0)); };
    return {clamp(x0, W), clamp(x1, W), clamp(y0, H), clamp(y1, H)};
}

RayProjection PortRays::projection(int u, int v) const {
    const Ray& r = ray(u, v);
    RayProjection p;
    p.forward = r.s_origin > 0.0f;
    p.u_inf = u + double(r.u_inf);
    p.v_inf = v + double(r.v_inf);
    p.du = r.du;
    p.dv = r.dv;
    p.s_origin = r.s_origin;
    return p;
}

PortHit PortRays::hit(int u, int v, const Image& inv_depth, double z_near) const {
    const Ray& r = ray(u, v);
    const PortMarch<float> m = march(u, v);
    float s_near = float(1.001 / z_near);
    const int W = inv_depth.width, H = inv_depth.height, B = kPortStartBlock;
    if (const int w = port_start_window(m, s_near, W, H); w >= 0) {
        // the window's nearest surface, pixel by pixel (window_nearest's, by blocks)
        const int bw = (W + B - 1) / B, bx = w % bw, by = w / bw;
        float nearest = 0.0f;
        for (int y = std::max(B * (by - 1), 0); y < std::min(B * (by + 2), H); ++y)
            for (int x = std::max(B * (bx - 1), 0); x < std::min(B * (bx + 2), W); ++x)
                nearest = std::max(nearest, inv_depth.at(x, y));
        s_near = port_start_s(s_near, nearest);
    }
    const PortCrossing<float> c = march_port_ray(inv_depth, m, s_near);
    PortHit h;
    h.kind = c.kind;
    if (c.kind != PortHitKind::Surface) return h;
    h.z = 1.0f / c.s;
    h.t = float((float(h.z) - r.oz) / r.dz);
    h.u = c.u;
    h.v = c.v;
    h.taps.count = c.taps.count;
    for (int i = 0; i < 4; ++i) {
        h.taps.x[i] = c.taps.x[i];
        h.taps.y[i] = c.taps.y[i];
        h.taps.w[i] = c.taps.w[i];
    }
    h.taps.inv_z = c.taps.inv_z;
    return h;
}

double nearest_surface(const Image& depth) {
    return tbb::parallel_reduce(
        tbb::blocked_range<int>(0, depth.height), std::numeric_limits<double>::infinity(),
        [&](const tbb::blocked_range<int>& rows, double z) {
            for (int v = rows.begin(); v < rows.end(); ++v) {
                const float* row = depth.row(v);
                for (int u = 0; u < depth.width; ++u)
                    if (has_surface(row[u])) z = std::min(z, double(row[u]));
            }
            return z;
        },
        [](double a, double b) { return std::min(a, b); });
}

}  // namespace deepsea

namespace deepsea {

void window_row_maxima(const float* inv, int W, float* out) {
    const int B = kPortStartBlock, full = W / B;
    for (int bx = 0; bx < full; ++bx) {
        float m = 0.0f;
        for (int k = 0; k < B; ++k) m = std::max(m, inv[B * bx + k]);
        out[bx] = m;
    }
    if (full * B < W) out[full] = *std::max_element(inv + full * B, inv + W);
}

void window_nearest_rows(const Image& rows, Image& out, Image& scratch) {
    const int bw = rows.width, H = rows.height, B = kPortStartBlock, bh = (H + B - 1) / B;
    if (out.width != bw || out.height != bh || out.channels != 1) out = Image(bw, bh, 1);
    if (scratch.width != bw || scratch.height != bh || scratch.channels != 1)
        scratch = Image(bw, bh, 1);
    // Each block's largest inverse depth, then the largest of the 3 x 3 blocks around each.
    for (int by = 0; by < bh; ++by) {
        float* o = scratch.row(by);
        std::fill_n(o, bw, 0.0f);
        for (int y = B * by; y < std::min(B * (by + 1), H); ++y) {
            const float* r = rows.row(y);
            for (int x = 0; x < bw; ++x) o[x] = std::max(o[x], r[x]);
        }
    }
    for (int by = 0; by < bh; ++by) {
        float* o = out.row(by);
        for (int bx = 0; bx < bw; ++bx) {
            float m = 0.0f;
            for (int y = std::max(by - 1, 0); y <= std::min(by + 1, bh - 1); ++y)
                for (int x = std::max(bx - 1, 0); x <= std::min(bx + 1, bw - 1); ++x)
                    m = std::max(m, scratch.at(x, y));
            o[bx] = m;
        }
    }
}

void window_nearest(const Image& inv, Image& out, Image& scratch) {
    const int W = inv.width, H = inv.height, B = kPortStartBlock;
    Image rows((W + B - 1) / B, H, 1);
    for (int y = 0; y < H; ++y) window_row_maxima(inv.row(y), W, rows.row(y));
    window_nearest_rows(rows, out, scratch);
}

}  // namespace deepsea
