// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt) so that GCC calls
// glibc's vector math (libmvec) for exp/acos/sqrt; target_clones picks AVX2 where available.
// Open water arrives as z == 0 (the compositor sanitises NaN/inf before calling).

#include "deepsea/runtime/lamps.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "clones.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/lamp.h"
#include "deepsea/optics/normals.h"
#include "kernels.h"
#include "lamp_field_rows.h"

namespace deepsea {

AnalyticLamps::AnalyticLamps(const Rig& rig, const Water& water, std::vector<LampField> scattered,
                             ShadowSettings shadows)
    : m_rig(rig), m_water(water), m_scattered(std::move(scattered)), m_shadow_settings(shadows) {
    if (shadows.enabled && !(shadows.thickness > 0.0 && std::isfinite(shadows.thickness))) {
        throw ConfigError("shadows: thickness must be > 0 m and finite");
    }
    if (shadows.enabled && shadows.step < 1) throw ConfigError("shadows: step must be >= 1 pixel");
    for (const Light& L : m_rig.lights) m_rids.emplace_back(L.rid);
    if (!m_scattered.empty() && m_scattered.size() != m_rig.lights.size()) {
        throw AssetError("multiple scattering: " + std::to_string(m_scattered.size()) +
                         " lamp fields for " + std::to_string(m_rig.lights.size()) + " lamps");
    }
}

namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// Adds one lamp's irradiance to the planar RGB row (First: writes it, so that the row needs no
/// zeroing pass; a lamp's term is +0 or positive, and 0 + x is x; unshadowed rows only: a
/// second instantiation in the shadowed clone changed GCC's fused multiply-adds there, and with
/// every lamp lit it must give the unshadowed row's bits): with its Gaussian RID (one
/// exponential a channel, lamp.h's gaussian_lamp_term), or with RID 1 (tabulated RIDs: the
/// row written, not added to; the caller scales it by the RID at scratch_theta). Shadowed: times
/// the lamp's visibility per pixel (vis). Inlined into each clone below. The exponentials and arc
/// cosines are core/fast_math.h's, inline (libmvec's, called per 8 values, were 8.5 % of a JPEG
/// sequence's CPU time): within a few float roundings of the exact
/// (tests/unit/core/fast_math_test.cpp; the rows against optics in double to 1e-5:
/// AnalyticLamps.GaussianLampsMatchOptics).
template <bool Gaussian, bool Shadowed, bool First = false>
[[gnu::always_inline]] inline void lamp_rows(const Light& L, const Rgb& c, const RowGeometry& g,
                                             const float* __restrict vis, float* __restrict e,
                                             float* __restrict scratch_theta) {
    const int n = g.n;
    const float lx = float(L.position.x), ly = float(L.position.y), lz = float(L.position.z);
    const Vec3T<float> axis{float(L.direction.x), float(L.direction.y), float(L.direction.z)};
    const float sig = float(L.rid.sigma_deg * kDegToRad);
    const float cutoff = float(L.rid.cutoff_deg * kDegToRad);
    const float cr = float(c.r), cg = float(c.g), cb = float(c.b);
    const float ir = float(L.intensity.r), ig = float(L.intensity.g), ib = float(L.intensity.b);
    float* __restrict er = e;
    float* __restrict eg = e + n;
    float* __restrict eb = e + 2 * n;
    const float* __restrict px = g.x;
    const float* __restrict py = g.y;
    const float* __restrict pz = g.z;
    const float* __restrict nx = g.nx;
    const float* __restrict ny = g.ny;
    const float* __restrict nz = g.nz;
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        // the equations are optics' (lamp.h); here only the row layout and the open-water mask
        const LampGeometry<float> lg =
            lamp_geometry({lx - px[u], ly - py[u], lz - pz[u]}, {nx[u], ny[u], nz[u]}, axis);
        const float theta = lamp_angle<FastMath>(lg.cos_theta);
        float spread = pz[u] > 0.0f ? lamp_spread(lg.d1, lg.cos_n) : 0.0f;
        spread = theta > cutoff ? 0.0f : spread;
        if constexpr (Shadowed) spread *= vis[u];
        if constexpr (Gaussian && First) {
            er[u] = gaussian_lamp_term<FastMath>(ir, theta, sig, spread, cr, lg.d1);
            eg[u] = gaussian_lamp_term<FastMath>(ig, theta, sig, spread, cg, lg.d1);
            eb[u] = gaussian_lamp_term<FastMath>(ib, theta, sig, spread, cb, lg.d1);
        } else if constexpr (Gaussian) {
            er[u] += gaussian_lamp_term<FastMath>(ir, theta, sig, spread, cr, lg.d1);
            eg[u] += gaussian_lamp_term<FastMath>(ig, theta, sig, spread, cg, lg.d1);
            eb[u] += gaussian_lamp_term<FastMath>(ib, theta, sig, spread, cb, lg.d1);
        } else {
            // (written: the row holds this lamp alone, scaled by its RID afterwards)
            scratch_theta[u] = theta;
            er[u] = lamp_term<FastMath>(ir, 1.0f, spread, cr, lg.d1);
            eg[u] = lamp_term<FastMath>(ig, 1.0f, spread, cg, lg.d1);
            eb[u] = lamp_term<FastMath>(ib, 1.0f, spread, cb, lg.d1);
        }
    }
}

DEEPSEA_CLONES
void add_gaussian_lamp(const Light& L, const Rgb& c, const RowGeometry& g, float* e, bool first) {
    if (first) {
        lamp_rows<true, false, true>(L, c, g, nullptr, e, nullptr);
    } else {
        lamp_rows<true, false>(L, c, g, nullptr, e, nullptr);
    }
}

DEEPSEA_CLONES
void add_unit_lamp(const Light& L, const Rgb& c, const RowGeometry& g, float* e,
                   float* scratch_theta) {
    lamp_rows<false, false>(L, c, g, nullptr, e, scratch_theta);
}

DEEPSEA_CLONES
void add_shadowed_gaussian_lamp(const Light& L, const Rgb& c, const RowGeometry& g,
                                const float* vis, float* e) {
    lamp_rows<true, true>(L, c, g, vis, e, nullptr);
}

DEEPSEA_CLONES
void add_shadowed_unit_lamp(const Light& L, const Rgb& c, const RowGeometry& g, const float* vis,
                            float* e, float* scratch_theta) {
    lamp_rows<false, true>(L, c, g, vis, e, scratch_theta);
}

/// Spacing of the points where the scattered light's coefficients are computed, as an angle
/// seen from the camera (radians): 8 px at fx = 600. The field varies on the scale of its table
/// (5 degrees, 15 % in distance): interpolating over that stays within 1 % of the exact value
/// (measured 0.6 %; twice the spacing 1.4 %), at 1/64 of the table lookups on a frame's grid
/// (AnalyticLamps.InterpolatedScatteredLightMatchesExactOnSmoothSurfaces,
/// Compositor.ScatteredLampLightOnTheFrameGridMatchesExact).
constexpr double kScatterAngle = 8.0 / 600.0;

/// Points every `step` pixels along a row (no frame grid, and rows of another size).
constexpr int kRowStep = 8;

/// Adds one lamp's scattered light, as quadratic-form coefficients (camera frame, times the
/// lamp's intensity), at K points (x, y, z) to the planes C[(c * kQuadraticCount + i) * K + k].
DEEPSEA_CLONES
void add_scattered_coefficients(const Light& L, const LampField& field, int K,
                                const float* __restrict x, const float* __restrict y,
                                const float* __restrict z, float* __restrict tmp,
                                float* __restrict C) {
    lamp_field_rows(L, field, K, x, y, z, tmp);
    for (int c = 0; c < 3; ++c) {
        const float I = float(L.intensity[c]);
        float* __restrict dst = C + c * kQuadraticCount * K;
        const float* __restrict src = tmp + c * kQuadraticCount * K;
#pragma omp simd
        for (int i = 0; i < kQuadraticCount * K; ++i) dst[i] += I * src[i];
    }
}

/// Adds the coefficients' irradiance to a planar row of n pixels, the coefficients (planes of K
/// points, every `step` pixels and the last) linear between points: E(n) = the quadratic
/// form at the pixel's normal. The points' depths are z0 (and z1, the grid row below, where
/// the row's coefficients were interpolated between grid rows): pixels not on the surface of
/// every point they are interpolated from (or open water) are skipped and flagged, and the
/// caller evaluates them exactly. The flags are int, not bytes: with a byte store in the loop
/// the compiler vectorizes 32 pixels at a time, and a segment (8 px at fx = 600) then ran in
/// its scalar remainder.
DEEPSEA_CLONES
void add_interpolated(int n, int K, int step, const float* C, const float* z0, const float* z1,
                      const float* __restrict z, const float* __restrict nx,
                      const float* __restrict ny, const float* __restrict nz, float* __restrict er,
                      float* __restrict eg, float* __restrict eb, int* __restrict flag) {
    for (int k = 0; k + 1 < K || (K == 1 && k == 0); ++k) {
        const int u0 = k * step, ub = std::min(u0 + step, n - 1);
        const int u1 = k + 2 >= K ? n : ub;  // the last segment includes the last pixel
        const int k1 = K == 1 ? k : k + 1;
        float c0[3 * kQuadraticCount], dc[3 * kQuadraticCount];
        for (int i = 0; i < 3 * kQuadraticCount; ++i) {
            c0[i] = C[i * K + k];
            dc[i] = C[i * K + k1] - c0[i];
        }
        const float za = z0[k], zb = z0[k1], zc = z1[k], zd = z1[k1];
        const float inv = ub > u0 ? 1.0f / float(ub - u0) : 0.0f;
#pragma omp simd
        for (int u = u0; u < u1; ++u) {
            const float zu = z[u];
            const bool same = zu > 0.0f && za > 0.0f && zb > 0.0f && zc > 0.0f && zd > 0.0f &&
                              same_surface(za, zu) && same_surface(zb, zu) &&
                              same_surface(zc, zu) && same_surface(zd, zu);
            flag[u] = zu > 0.0f && !same ? 1 : 0;
            const float w = float(u - u0) * inv;
            const float x = nx[u], y = ny[u], zz = nz[u];
            const float m[kQuadraticCount] = {
                1.0f, x, y, zz, x * x, y * y, zz * zz, 2.0f * x * y, 2.0f * x * zz, 2.0f * y * zz};
            float E[3];
#pragma GCC unroll 3
            for (int c = 0; c < 3; ++c) {
                E[c] = 0.0f;
#pragma GCC unroll 10
                for (int i = 0; i < kQuadraticCount; ++i) {
                    E[c] += (c0[c * kQuadraticCount + i] + w * dc[c * kQuadraticCount + i]) * m[i];
                }
            }
            er[u] += same && E[0] > 0.0f ? E[0] : 0.0f;
            eg[u] += same && E[1] > 0.0f ? E[1] : 0.0f;
            eb[u] += same && E[2] > 0.0f ? E[2] : 0.0f;
        }
    }
}

}  // namespace

namespace {

/// Coefficient points along n pixels: every `step` pixels and the last one.
int scatter_points(int n, int step) { return (n - 1 + step - 1) / step + 1; }

}  // namespace

void AnalyticLamps::begin_frame(const Camera& cam, const Image& zdepth) const {
    if (m_shadow_settings.enabled) m_shadows.compute(cam, zdepth, m_rig, m_shadow_settings);
    if (m_scattered.empty()) return;
    const int W = zdepth.width, H = zdepth.height;
    m_width = W;
    m_height = H;
    m_step = std::clamp(int(cam.fx * kScatterAngle), 1, 64);
    m_kx = scatter_points(W, m_step);
    m_ky = scatter_points(H, m_step);
    m_grid.resize(std::size_t(m_ky) * 3 * kQuadraticCount * m_kx);
    m_grid_z.resize(std::size_t(m_ky) * m_kx);
    tbb::parallel_for(0, m_ky, [&](int j) {
        const int v = std::min(j * m_step, H - 1);
        thread_local std::vector<float> px, py, tmp;
        px.resize(m_kx);
        py.resize(m_kx);
        tmp.resize(3 * kQuadraticCount * std::size_t(m_kx));
        float* pz = m_grid_z.data() + std::size_t(j) * m_kx;
        for (int i = 0; i < m_kx; ++i) {
            const int u = std::min(i * m_step, W - 1);
            const float z = zdepth.at(u, v);
            pz[i] = has_surface(z) ? z : 0.0f;  // as the compositor's rows see it
            px[i] = float(cam.ray_x(u)) * pz[i];
            py[i] = float(cam.ray_y(v)) * pz[i];
        }
        float* C = m_grid.data() + std::size_t(j) * 3 * kQuadraticCount * m_kx;
        std::fill(C, C + 3 * kQuadraticCount * m_kx, 0.0f);
        for (std::size_t l = 0; l < m_scattered.size(); ++l) {
            add_scattered_coefficients(m_rig.lights[l], m_scattered[l], m_kx, px.data(), py.data(),
                                       pz, tmp.data(), C);
        }
    });
}

void AnalyticLamps::add_scattered(const RowGeometry& g, float* out) const {
    const int n = g.n;
    if (n < 1) return;
    const bool grid = m_width == n && m_ky > 0 && g.v >= 0 && g.v < m_height;
    const int step = grid ? m_step : kRowStep;
    const int K = scatter_points(n, step);
    const std::size_t planes = 3 * kQuadraticCount * std::size_t(K);
    thread_local std::vector<float> px, py, pz, tmp, C;
    thread_local std::vector<int> flag;
    C.resize(planes);
    flag.resize(n);
    const float *z0, *z1;
    if (grid) {
        // The frame's grid: this row's coefficients between the grid rows around it.
        const int j0 = std::min(g.v / step, m_ky - 1), j1 = std::min(j0 + 1, m_ky - 1);
        const int v0 = std::min(j0 * step, m_height - 1), v1 = std::min(j1 * step, m_height - 1);
        const float wv = v1 > v0 ? float(g.v - v0) / float(v1 - v0) : 0.0f;
        const float* a = m_grid.data() + std::size_t(j0) * planes;
        const float* b = m_grid.data() + std::size_t(j1) * planes;
        for (std::size_t i = 0; i < planes; ++i) C[i] = a[i] + wv * (b[i] - a[i]);
        z0 = m_grid_z.data() + std::size_t(j0) * K;
        z1 = wv > 0.0f ? m_grid_z.data() + std::size_t(j1) * K : z0;
    } else {
        // No grid for rows of this size: points on the row itself.
        px.resize(K);
        py.resize(K);
        pz.resize(K);
        for (int k = 0; k < K; ++k) {
            const int u = std::min(k * step, n - 1);
            px[k] = g.x[u];
            py[k] = g.y[u];
            pz[k] = g.z[u];
        }
        tmp.resize(planes);
        std::fill(C.begin(), C.end(), 0.0f);
        for (std::size_t l = 0; l < m_scattered.size(); ++l) {
            add_scattered_coefficients(m_rig.lights[l], m_scattered[l], K, px.data(), py.data(),
                                       pz.data(), tmp.data(), C.data());
        }
        z0 = z1 = pz.data();
    }
    add_interpolated(n, K, step, C.data(), z0, z1, g.z, g.nx, g.ny, g.nz, out, out + n, out + 2 * n,
                     flag.data());
    // Pixels across a depth edge from a coefficient point: the same coefficients, computed at
    // the pixel itself (one point).
    float q[3 * kQuadraticCount], qtmp[3 * kQuadraticCount];
    for (int u = 0; u < n; ++u) {
        if (!flag[u]) continue;
        std::fill(q, q + 3 * kQuadraticCount, 0.0f);
        for (std::size_t l = 0; l < m_scattered.size(); ++l) {
            add_scattered_coefficients(m_rig.lights[l], m_scattered[l], 1, g.x + u, g.y + u,
                                       g.z + u, qtmp, q);
        }
        for (int c = 0; c < 3; ++c) {
            const float e =
                quadratic_irradiance(q + c * kQuadraticCount, 1, g.nx[u], g.ny[u], g.nz[u]);
            out[c * n + u] += e > 0.0f ? e : 0.0f;
        }
    }
}

void AnalyticLamps::irradiance_row(const RowGeometry& g, float* out) const {
    const int n = g.n;
    thread_local std::vector<float> theta, part, rid;
    theta.resize(n);
    const bool shadowed = m_shadow_settings.enabled && m_shadows.width() == n && g.v >= 0 &&
                          g.v < m_shadows.height() && m_shadows.lamps() == m_rig.lights.size();
    // The first lamp writes the row where it can (an unshadowed Gaussian lamp, or a tabulated
    // one: its terms times its RID), so that the row needs no zeroing pass; a lamp's term is
    // +0 or positive, and 0 + x is x. Otherwise the row starts from zero.
    const bool gaussian0 = !m_rig.lights.empty() && m_rig.lights[0].rid.kind == Rid::Kind::Gaussian;
    const bool written = !m_rig.lights.empty() && !(gaussian0 && shadowed);
    if (!written) std::fill(out, out + 3 * std::size_t(n), 0.0f);
    for (std::size_t l = 0; l < m_rig.lights.size(); ++l) {
        const Light& L = m_rig.lights[l];
        const float* vis = shadowed ? m_shadows.row(l, g.v) : nullptr;
        if (L.rid.kind == Rid::Kind::Gaussian) {
            if (vis) {
                add_shadowed_gaussian_lamp(L, m_water.c, g, vis, out);
            } else {
                add_gaussian_lamp(L, m_water.c, g, out, l == 0);
            }
        } else {
            part.resize(3 * std::size_t(n));
            rid.resize(n);
            if (vis) {
                add_shadowed_unit_lamp(L, m_water.c, g, vis, part.data(), theta.data());
            } else {
                add_unit_lamp(L, m_water.c, g, part.data(), theta.data());
            }
            m_rids[l](n, theta.data(), rid.data());
            kernels::add_scaled(n, rid.data(), part.data(), out, l == 0);
        }
    }
    if (!m_scattered.empty()) add_scattered(g, out);
}

}  // namespace deepsea
