// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt); depth arrives
// sanitised (open water z == 0, never NaN or inf), as the compositor guarantees.

#include "deepsea/runtime/asset_backscatter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "clones.h"
#include "deepsea/core/error.h"

namespace deepsea {

namespace {

/// Buckets of at most the thinnest slab's thickness, so a bucket's slab is right or one short.
int bucket_count(const std::vector<double>& z) {
    double thinnest = z.back();
    for (std::size_t k = 0; k + 1 < z.size(); ++k) thinnest = std::min(thinnest, z[k + 1] - z[k]);
    const double n = std::ceil(z.back() / thinnest) + 1.0;
    return int(std::clamp(n, 1024.0, double(1 << 20)));
}

struct RowTaps {
    int off0, off1;  ///< value offsets of the row's two lattice rows
    float w;                 ///< weight of the second
};

/// B for one image row, planar RGB out. Column offsets/weights per pixel, the row's two
/// lattice rows fixed; depth slab from the bucket table plus at most one step.
DEEPSEA_CLONES
void lookup_row(int n, const float* __restrict z, const float* __restrict values,
                const int* __restrict col0, const int* __restrict col1,
                const float* __restrict colw, RowTaps r, const float* __restrict zs,
                const float* __restrict znext, const float* __restrict inv_h,
                const int* __restrict bucket, int last_bucket, float bucket_scale, float z_max,
                float* __restrict out) {
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        // z == 0 (open water) looks up z_max, as does any depth beyond it.
        const float zz = z[u] > 0.0f ? std::min(z[u], z_max) : z_max;
        int k = bucket[std::min(int(zz * bucket_scale), last_bucket)];
        k += znext[k] <= zz ? 1 : 0;
        const float wz = std::clamp((zz - zs[k]) * inv_h[k], 0.0f, 1.0f);
        const int kk = 3 * k;
        const float* p00 = values + col0[u] + r.off0 + kk;
        const float* p10 = values + col1[u] + r.off0 + kk;
        const float* p01 = values + col0[u] + r.off1 + kk;
        const float* p11 = values + col1[u] + r.off1 + kk;
        const float cw = colw[u];
        for (int ch = 0; ch < 3; ++ch) {
            const float a = p00[ch] + wz * (p00[ch + 3] - p00[ch]);
            const float b = p10[ch] + wz * (p10[ch + 3] - p10[ch]);
            const float c = p01[ch] + wz * (p01[ch + 3] - p01[ch]);
            const float d = p11[ch] + wz * (p11[ch + 3] - p11[ch]);
            const float top = a + cw * (b - a);
            const float bot = c + cw * (d - c);
            out[ch * n + u] = top + r.w * (bot - top);
        }
    }
}

}  // namespace

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
    m_rows = taps(camera.height, camera.fy, camera.cy, ac.fy, ac.cy, l.nj);
    const std::vector<Tap> cols = taps(camera.width, camera.fx, camera.cx, ac.fx, ac.cx, l.ni);
    // 32-bit offsets let the lookup loop vectorise (gathers); 2^31 floats would be 8 GB.
    if (asset.values.size() >= std::size_t(std::numeric_limits<int>::max())) {
        throw AssetError("asset too large for the runtime's lookup (" +
                         std::to_string(asset.values.size()) + " values)");
    }
    const int column_floats = 3 * l.nj * l.nk();
    for (const Tap& t : cols) {
        m_col0.push_back(t.i0 * column_floats);
        m_col1.push_back(t.i1 * column_floats);
        m_colw.push_back(t.w);
    }

    const int K = l.slabs();
    m_z.assign(l.z.begin(), l.z.end());
    m_inv_h.resize(K);
    m_znext.resize(K);
    for (int k = 0; k < K; ++k) {
        m_inv_h[k] = float(1.0 / (l.z[k + 1] - l.z[k]));
        m_znext[k] = k + 1 < K ? float(l.z[k + 1]) : std::numeric_limits<float>::max();
    }
    const int buckets = bucket_count(l.z);
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
    const Tap t = m_rows[v];
    const int nk3 = 3 * l.nk();
    const RowTaps r{t.i0 * nk3, t.i1 * nk3, t.w};
    lookup_row(n, z, m_asset.values.data(), m_col0.data(), m_col1.data(), m_colw.data(), r,
               m_z.data(), m_znext.data(), m_inv_h.data(), m_bucket.data(),
               int(m_bucket.size()) - 1, m_bucket_scale, m_z.back(), out);
}

}  // namespace deepsea
