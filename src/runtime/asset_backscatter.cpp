#include "deepsea/runtime/asset_backscatter.h"

#include <algorithm>
#include <cmath>

namespace deepsea {

AssetBackscatter::AssetBackscatter(const Asset& asset, const Camera& camera) : m_asset(asset) {
    check_camera(asset, camera);
    const Camera& ac = asset.info.camera;
    const Lattice& l = asset.lattice();
    auto taps = [&](int pixels, double f, double c, double fa, double ca, int count) {
        std::vector<Tap> out(pixels);
        for (int p = 0; p < pixels; ++p) {
            const double pa = ca + (p - c) * fa / f;  // same ray, asset pixel coordinates
            const double x = std::clamp(pa / l.step, 0.0, double(count - 1));
            Tap t;
            t.i0 = std::min(int(x), std::max(count - 2, 0));
            t.i1 = std::min(t.i0 + 1, count - 1);
            t.w = float(x - t.i0);
            out[p] = t;
        }
        return out;
    };
    m_cols = taps(camera.width, camera.fx, camera.cx, ac.fx, ac.cx, l.ni);
    m_rows = taps(camera.height, camera.fy, camera.cy, ac.fy, ac.cy, l.nj);

    const int K = l.slabs();
    m_z.assign(l.z.begin(), l.z.end());
    m_inv_h.resize(K);
    for (int k = 0; k < K; ++k) m_inv_h[k] = float(1.0 / (l.z[k + 1] - l.z[k]));
    const int buckets = 4 * 1024;
    m_bucket_scale = float(buckets / l.z_max());
    m_bucket.resize(buckets + 1);
    for (int b = 0, k = 0; b <= buckets; ++b) {
        const double zb = b / double(m_bucket_scale);
        while (k < K - 1 && l.z[k + 1] <= zb) ++k;
        m_bucket[b] = k;
    }
}

void AssetBackscatter::backscatter_row(int v, int n, const float* z, float* out) const {
    const Lattice& l = m_asset.lattice();
    const Tap r = m_rows[v];
    const float* base = m_asset.values.data();
    const std::size_t nk = std::size_t(l.nk());
    const int K = l.slabs();
    for (int u = 0; u < n; ++u) {
        const Tap c = m_cols[u];
        // z == 0 is open water after the compositor's sanitising: look up z_max, as beyond it.
        const float zz = z[u] > 0.0f ? std::min(z[u], m_z.back()) : m_z.back();
        int k = m_bucket[std::min(int(zz * m_bucket_scale), int(m_bucket.size()) - 1)];
        while (k < K - 1 && m_z[k + 1] <= zz) ++k;
        const float wz = std::min((zz - m_z[k]) * m_inv_h[k], 1.0f);
        const DepthPosition dp{k, wz};
        const float* p00 = base + ((std::size_t(c.i0) * l.nj + r.i0) * nk + dp.k) * 3;
        const float* p10 = base + ((std::size_t(c.i1) * l.nj + r.i0) * nk + dp.k) * 3;
        const float* p01 = base + ((std::size_t(c.i0) * l.nj + r.i1) * nk + dp.k) * 3;
        const float* p11 = base + ((std::size_t(c.i1) * l.nj + r.i1) * nk + dp.k) * 3;
        for (int ch = 0; ch < 3; ++ch) {
            auto lerpz = [&](const float* p) { return p[ch] + wz * (p[ch + 3] - p[ch]); };
            const float top = lerpz(p00) + c.w * (lerpz(p10) - lerpz(p00));
            const float bot = lerpz(p01) + c.w * (lerpz(p11) - lerpz(p01));
            out[ch * n + u] = top + r.w * (bot - top);
        }
    }
}

}  // namespace deepsea
