// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt); depth arrives
// sanitised (open water z == 0, never NaN or inf), as the compositor guarantees.

#include "deepsea/runtime/asset_backscatter.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "backscatter_lookup.h"
#include "backscatter_rows.h"
#include "clones.h"
#include "depth_slabs.h"

namespace deepsea {

namespace {

/// The slabs [lo, hi] that pixels [begin, end) use: lo = min(lo, min_u k_u),
/// hi = max(hi, max_u k_u). A span is one lattice column's pixels (16 at the demo's step), so
/// eight at a time in explicit vectors, the rest one by one: an `omp simd` reduction's set-up
/// and remainder cost more than the span's own minimum and maximum (113 instructions a span of
/// 16, callgrind).
DEEPSEA_CLONES
void slab_range(int begin, int end, const int* __restrict k, int& lo, int& hi) {
    typedef int Int8 __attribute__((vector_size(32)));
    int a = lo, b = hi;
    int u = begin;
    if (end - u >= 8) {
        Int8 mn, mx;
        std::memcpy(&mn, k + u, sizeof mn);
        mx = mn;
        for (u += 8; u + 8 <= end; u += 8) {
            Int8 x;
            std::memcpy(&x, k + u, sizeof x);
            mn = x < mn ? x : mn;
            mx = x > mx ? x : mx;
        }
        for (int i = 0; i < 8; ++i) {
            a = std::min(a, mn[i]);
            b = std::max(b, mx[i]);
        }
    }
    for (; u < end; ++u) {
        a = std::min(a, k[u]);
        b = std::max(b, k[u]);
    }
    lo = a;
    hi = b;
}

/// Vertical interpolation once per row rather than per pixel: samples [m0, m1) of one lattice
/// column, blended between the row's two lattice rows a and b by the row weight w,
///   S_i[m] = B(i, j0, m) + w_v (B(i, j1, m) - B(i, j0, m))   (m = 3k + c).
DEEPSEA_CLONES
void blend_rows(int m0, int m1, const float* __restrict a, const float* __restrict b, float w,
                float* __restrict out) {
#pragma omp simd
    for (int m = m0; m < m1; ++m) out[m] = lerp(a[m], b[m], w);
}

}  // namespace

AssetBackscatter::AssetBackscatter(const Asset& asset, const Camera& camera) : m_asset(asset) {
    check_camera(asset, camera);
    const Camera& ac = asset.info.camera;
    const Lattice& l = asset.lattice();
    // Asset::sample's cells, in float, once per image row and column.
    auto taps = [&](int pixels, double f, double c, double fa, double ca, int count) {
        std::vector<LatticeCell<float>> out(pixels);
        for (int p = 0; p < pixels; ++p) {
            const double pa = ca + (p - c) * fa / f;  // same ray, asset pixel coordinates
            const LatticeCell<double> t = lattice_cell(pa / l.step, count);
            out[p] = {t.i0, t.i1, float(t.w)};
        }
        return out;
    };
    m_rows = taps(camera.height, camera.fy, camera.cy, ac.fy, ac.cy, l.nj);
    const std::vector<LatticeCell<float>> cols =
        taps(camera.width, camera.fx, camera.cx, ac.fx, ac.cx, l.ni);
    // Offsets into a row's slice (blend_rows): column i's samples start at 3 nk i.
    const int block = 3 * l.nk();
    for (int u = 0; u < camera.width; ++u) {
        const LatticeCell<float>& t = cols[u];
        m_col0.push_back(t.i0 * block);
        m_col1.push_back(t.i1 * block);
        m_colw.push_back(t.w);
        if (m_spans.empty() || m_spans.back().i0 != t.i0 || m_spans.back().i1 != t.i1) {
            m_spans.push_back({u, u, t.i0, t.i1});
        }
        m_spans.back().end = u + 1;
    }
    for (const Span& sp : m_spans) m_span_end.push_back(sp.end);

    m_slabs = std::make_shared<const DepthSlabs>(l.z);
    // (to half the allowed 1e-3 of B: the rest is the other approximations' share)
    BackscatterRowBounds rb =
        backscatter_row_bounds(l, asset.values.data(), l.step * camera.fy / ac.fy,
                               backscatter_row_stride(camera.fy), 5e-4);
    // B is linear in v between lattice rows: a pair of looked-up rows whose lattice coordinates
    // (as taps' above) have no lattice row strictly between them, within the lattice, has no
    // kink between them.
    const int H = camera.height, R = rb.stride;
    for (int v0 = 0; v0 < H - 1; v0 += R) {
        const int v1 = std::min(v0 + R, H - 1);
        const auto x = [&](int v) {
            return (ac.cy + (v - camera.cy) * ac.fy / camera.fy) / l.step;
        };
        const double x0 = x(v0), x1 = x(v1);
        const bool inside = x0 >= 0.0 && x1 <= l.nj - 1;
        rb.kinked.push_back(!(inside && x1 <= std::floor(x0) + 1.0));
    }
    m_row_bounds = std::make_shared<const BackscatterRowBounds>(std::move(rb));
}

void AssetBackscatter::backscatter_pixels(int v, int n, const float* z, int count, const int* cols,
                                          float* out) const {
    const Lattice& l = m_asset.lattice();
    const LatticeCell<float> t = m_rows[v];
    const int block = 3 * l.nk();
    const std::size_t stride = std::size_t(l.nj) * block;
    const float* a = m_asset.values.data() + std::size_t(t.i0) * block;
    const float* b = m_asset.values.data() + std::size_t(t.i1) * block;
    for (int q = 0; q < count; ++q) {
        const int u = cols[q];
        if (u < 0 || u >= n) continue;
        int k;
        float wz;
        depth_cells_each(1, z + u, *m_slabs, &k, &wz);
        // as backscatter_row: the lattice rows blended first, then depth, then columns
        const std::size_t i0 = std::size_t(m_col0[u] / block) * stride + 3 * k;
        const std::size_t i1 = std::size_t(m_col1[u] / block) * stride + 3 * k;
        for (int c = 0; c < 3; ++c) {
            const float p0 = lerp(a[i0 + c], b[i0 + c], t.w);
            const float q0 = lerp(a[i0 + 3 + c], b[i0 + 3 + c], t.w);
            const float p1 = lerp(a[i1 + c], b[i1 + c], t.w);
            const float q1 = lerp(a[i1 + 3 + c], b[i1 + 3 + c], t.w);
            out[3 * u + c] = lerp(lerp(p0, q0, wz), lerp(p1, q1, wz), m_colw[u]);
        }
    }
}

void AssetBackscatter::backscatter_row(int v, int n, const float* z, float* out_rgb) const {
    const Lattice& l = m_asset.lattice();
    const LatticeCell<float> t = m_rows[v];
    const int block = 3 * l.nk();
    const std::size_t stride = std::size_t(l.nj) * block;  // from column i to i + 1
    struct Scratch {
        std::vector<float> slice, wz;
        std::vector<int> slab, lo, hi;
    };
    thread_local Scratch s;
    s.slice.resize(std::size_t(l.ni) * block + 1);  // + 1: lookup_row's fourth lane
    s.wz.resize(n);
    s.slab.resize(n);
    depth_cells(n, z, *m_slabs, s.slab.data(), s.wz.data());
    // Only the slabs the row's pixels use are blended (a smooth surface uses one to three per
    // lattice column of the 64 or so): each column's range over the pixels on either side.
    s.lo.assign(l.ni, l.slabs());
    s.hi.assign(l.ni, -1);
    for (const Span& sp : m_spans) {
        if (sp.begin >= n) break;
        int lo = l.slabs(), hi = -1;
        slab_range(sp.begin, std::min(sp.end, n), s.slab.data(), lo, hi);
        for (const int i : {sp.i0, sp.i1}) {
            s.lo[i] = std::min(s.lo[i], lo);
            s.hi[i] = std::max(s.hi[i], hi);
        }
    }
    const float* values = m_asset.values.data();
    const float* a = values + std::size_t(t.i0) * block;
    const float* b = values + std::size_t(t.i1) * block;
    for (int i = 0; i < l.ni; ++i) {
        if (s.hi[i] < 0) continue;
        // samples lo .. hi + 1, three floats each
        blend_rows(3 * s.lo[i], 3 * (s.hi[i] + 2), a + i * stride, b + i * stride, t.w,
                   s.slice.data() + std::size_t(i) * block);
    }
    const LookupColumns cols{m_col0.data(), m_col1.data(), m_colw.data(), m_span_end.data(),
                             int(m_span_end.size())};
    lookup_row(n, s.slice.data(), cols, s.slab.data(), s.wz.data(), out_rgb);
}

}  // namespace deepsea
