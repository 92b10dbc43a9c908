#include "deepsea/runtime/port_backscatter.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "deepsea/asset/lattice.h"

namespace deepsea {

PortBackscatter::PortBackscatter(const Asset& asset, const PortRays& rays)
    : m_asset(asset), m_rays(rays) {
    const Camera& cam = rays.camera();
    check_camera(asset, cam);
    const Camera& ac = asset.info.camera;
    const Lattice& l = asset.lattice();
    m_z.assign(l.z.begin(), l.z.end());
    const int nk = l.nk();
    m_columns.resize(std::size_t(cam.width) * cam.height);
    tbb::parallel_for(0, cam.height, [&](int v) {
        for (int u = 0; u < cam.width; ++u) {
            const PortRays::Ray& r = rays.ray(u, v);
            const RayProjection p = rays.projection(u, v);
            // the vanishing point in the asset camera's pixels: the pinhole ray of direction w
            const double ua = ac.cx + (p.u_inf - cam.cx) * ac.fx / cam.fx;
            const double va = ac.cy + (p.v_inf - cam.cy) * ac.fy / cam.fy;
            const LatticeCell<double> ci = lattice_cell(ua / l.step, l.ni);
            const LatticeCell<double> cj = lattice_cell(va / l.step, l.nj);
            Column& c = m_columns[std::size_t(v) * cam.width + u];
            c.base = int(asset.index(ci.i0, cj.i0, 0));
            c.di = int(asset.index(ci.i1, cj.i0, 0)) - c.base;
            c.dj = int(asset.index(ci.i0, cj.i1, 0)) - c.base;
            c.wi = float(ci.w);
            c.wj = float(cj.w);
            const double s0 = double(r.ox) * r.dx + double(r.oy) * r.dy + double(r.oz) * r.dz;
            const double z_start = std::max(0.0, s0 * r.dz);
            c.z_off = float(z_start - r.oz);
            c.b0[0] = c.b0[1] = c.b0[2] = 0.0f;
            for (int ch = 0; ch < 3; ++ch) c.gain[ch] = 1.0f;
            float b[3];
            lookup(int(std::size_t(v) * cam.width + u), float(z_start), b);
            std::copy(b, b + 3, c.b0);
            // the asset's light is attenuated back to the camera centre, the port's only back
            // to the port (the housing holds no water)
            const double s_start = z_start / r.dz;
            for (int ch = 0; ch < 3; ++ch)
                c.gain[ch] = float(std::exp(asset.info.water.c[ch] * s_start));
        }
    });
    (void)nk;
}

void PortBackscatter::lookup(int pixel, float z, float* out) const {
    const Column& c = m_columns[pixel];
    const int K = int(m_z.size()) - 1;
    const float zz = std::clamp(z, 0.0f, float(m_z.back()));
    // the slab: binary search over the few dozen samples
    int k = int(std::upper_bound(m_z.begin(), m_z.end(), zz) - m_z.begin()) - 1;
    k = std::clamp(k, 0, K - 1);
    const float wz = std::clamp((zz - m_z[k]) / (m_z[k + 1] - m_z[k]), 0.0f, 1.0f);
    const float* p = m_asset.values.data() + c.base + 3 * k;
    const float w00 = (1 - c.wi) * (1 - c.wj), w10 = c.wi * (1 - c.wj), w01 = (1 - c.wi) * c.wj,
                w11 = c.wi * c.wj;
    for (int ch = 0; ch < 3; ++ch) {
        const auto at = [&](int off) { return lerp(p[off + ch], p[off + 3 + ch], wz); };
        out[ch] = c.gain[ch] * (w00 * at(0) + w10 * at(c.di) + w01 * at(c.dj) +
                                w11 * at(c.di + c.dj) - c.b0[ch]);
    }
}

void PortBackscatter::backscatter_row(int v, int n, const float* z, float* out) const {
    const int W = m_rays.camera().width;
    const float z_max = float(m_z.back());
    for (int u = 0; u < n; ++u) {
        const int pixel = v * W + u;
        lookup(pixel, z[u] > 0.0f ? z[u] + m_columns[pixel].z_off : z_max, out + 3 * u);
    }
}

}  // namespace deepsea
