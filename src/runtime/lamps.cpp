// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt) so that GCC calls
// glibc's vector math (libmvec) for exp/acos/sqrt; target_clones picks AVX2 where available.
// Open water arrives as z == 0 (the compositor sanitises NaN/inf before calling).

#include "deepsea/runtime/lamps.h"

#include <cmath>


#include "clones.h"

namespace deepsea {

AnalyticLamps::AnalyticLamps(const Rig& rig, const Water& water) : m_rig(rig), m_water(water) {}

namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// Adds one lamp's irradiance to the planar RGB row. Gaussian RID in-loop; tabulated RIDs
/// take the scalar interpolation after the vector part.
DEEPSEA_CLONES
void add_lamp(const Light& L, const Rgb& c, const RowGeometry& g, float* __restrict e,
              float* __restrict scratch_theta) {
    const int n = g.n;
    const float lx = float(L.position.x), ly = float(L.position.y), lz = float(L.position.z);
    const float ax = float(L.direction.x), ay = float(L.direction.y), az = float(L.direction.z);
    const bool gaussian = L.rid.kind == Rid::Kind::Gaussian;
    const float sig = float(L.rid.sigma_deg * kDegToRad);
    const float inv2s2 = gaussian ? 1.0f / (2.0f * sig * sig) : 0.0f;
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
        const float wx = lx - px[u], wy = ly - py[u], wz = lz - pz[u];
        const float d1sq = wx * wx + wy * wy + wz * wz;
        const float d1 = std::sqrt(d1sq);
        const float inv = 1.0f / d1;
        const float cosn = (nx[u] * wx + ny[u] * wy + nz[u] * wz) * inv;
        // angle between the lamp axis and the direction lamp -> P (= -w)
        float ct = -(ax * wx + ay * wy + az * wz) * inv;
        ct = ct > 1.0f ? 1.0f : (ct < -1.0f ? -1.0f : ct);
        const float theta = std::acos(ct);
        scratch_theta[u] = theta;
        float rid = gaussian ? std::exp(-theta * theta * inv2s2) : 1.0f;
        rid = theta > cutoff ? 0.0f : rid;
        const float geo = (cosn > 0.0f && pz[u] > 0.0f) ? rid * cosn / d1sq : 0.0f;
        er[u] += ir * geo * std::exp(-cr * d1);
        eg[u] += ig * geo * std::exp(-cg * d1);
        eb[u] += ib * geo * std::exp(-cb * d1);
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
}

}  // namespace deepsea
