// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt) so that GCC calls
// glibc's vector math (libmvec) for exp/acos/sqrt; target_clones picks AVX2 where available.
// Open water arrives as z == 0 (the compositor sanitises NaN/inf before calling).

#include "deepsea/runtime/lamps.h"

#include <cmath>

#include "clones.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/lamp.h"

namespace deepsea {

AnalyticLamps::AnalyticLamps(const Rig& rig, const Water& water, std::vector<LampField> scattered)
    : m_rig(rig), m_water(water), m_scattered(std::move(scattered)) {
    if (!m_scattered.empty() && m_scattered.size() != m_rig.lights.size()) {
        throw AssetError("multiple scattering: " + std::to_string(m_scattered.size()) +
                         " lamp fields for " + std::to_string(m_rig.lights.size()) + " lamps");
    }
}

namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// Adds one lamp's irradiance to the planar RGB row. Gaussian RID in-loop; tabulated RIDs
/// take the scalar interpolation after the vector part.
DEEPSEA_CLONES
void add_lamp(const Light& L, const Rgb& c, const RowGeometry& g, float* __restrict e,
              float* __restrict scratch_theta) {
    const int n = g.n;
    const float lx = float(L.position.x), ly = float(L.position.y), lz = float(L.position.z);
    const Vec3T<float> axis{float(L.direction.x), float(L.direction.y), float(L.direction.z)};
    const bool gaussian = L.rid.kind == Rid::Kind::Gaussian;
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
        const float theta = lamp_angle(lg.cos_theta);
        scratch_theta[u] = theta;
        float rid = gaussian ? gaussian_rid(theta, sig) : 1.0f;
        rid = theta > cutoff ? 0.0f : rid;
        const float spread = pz[u] > 0.0f ? lamp_spread(lg.d1, lg.cos_n) : 0.0f;
        er[u] += lamp_term(ir, rid, spread, cr, lg.d1);
        eg[u] += lamp_term(ig, rid, spread, cg, lg.d1);
        eb[u] += lamp_term(ib, rid, spread, cb, lg.d1);
    }
}

/// Adds one lamp's scattered light (its baked field, per unit intensity) to the planar row
/// (er, eg, eb); surface points (x, y, z) with normals (nx, ny, nz), open water where z == 0.
DEEPSEA_CLONES
void add_scattered(const Light& L, const LampField& field, int n, const float* __restrict x,
                   const float* __restrict y, const float* __restrict z, const float* __restrict nx,
                   const float* __restrict ny, const float* __restrict nz, float* __restrict er,
                   float* __restrict eg, float* __restrict eb) {
    Vec3 ex, ey;
    lamp_frame(L.direction, ex, ey);
    const LampFieldView<float> f(field);
    const Vec3T<float> o{float(L.position.x), float(L.position.y), float(L.position.z)};
    const Vec3T<float> fx{float(ex.x), float(ex.y), float(ex.z)};
    const Vec3T<float> fy{float(ey.x), float(ey.y), float(ey.z)};
    const Vec3T<float> fz{float(L.direction.x), float(L.direction.y), float(L.direction.z)};
    const float ir = float(L.intensity.r), ig = float(L.intensity.g), ib = float(L.intensity.b);
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        // into the lamp frame: the equation is optics' (lamp_field.h)
        const float qx = x[u] - o.x, qy = y[u] - o.y, qz = z[u] - o.z;
        float sr, sg, sb;
        lamp_field_irradiance(f, fx.x * qx + fx.y * qy + fx.z * qz,
                              fy.x * qx + fy.y * qy + fy.z * qz, fz.x * qx + fz.y * qy + fz.z * qz,
                              fx.x * nx[u] + fx.y * ny[u] + fx.z * nz[u],
                              fy.x * nx[u] + fy.y * ny[u] + fy.z * nz[u],
                              fz.x * nx[u] + fz.y * ny[u] + fz.z * nz[u], sr, sg, sb);
        const float surf = z[u] > 0.0f ? 1.0f : 0.0f;
        er[u] += surf * ir * sr;
        eg[u] += surf * ig * sg;
        eb[u] += surf * ib * sb;
    }
}

}  // namespace

void AnalyticLamps::irradiance_row(const RowGeometry& g, float* out) const {
    const int n = g.n;
    for (int i = 0; i < 3 * n; ++i) out[i] = 0.0f;
    thread_local std::vector<float> theta, part;
    theta.resize(n);
    for (const Light& L : m_rig.lights) {
        if (L.rid.kind == Rid::Kind::Gaussian) {
            add_lamp(L, m_water.c, g, out, theta.data());
        } else {
            part.assign(3 * std::size_t(n), 0.0f);
            add_lamp(L, m_water.c, g, part.data(), theta.data());
            for (int u = 0; u < n; ++u) {
                const float s = float(L.rid(theta[u]));
                out[u] += s * part[u];
                out[n + u] += s * part[n + u];
                out[2 * n + u] += s * part[2 * n + u];
            }
        }
    }
    for (std::size_t l = 0; l < m_scattered.size(); ++l) {
        add_scattered(m_rig.lights[l], m_scattered[l], n, g.x, g.y, g.z, g.nx, g.ny, g.nz, out,
                      out + n, out + 2 * n);
    }
}

}  // namespace deepsea
