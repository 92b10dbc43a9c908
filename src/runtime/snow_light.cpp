// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt), as lamps.cpp, so
// that GCC calls libmvec for exp/acos/sqrt; target_clones picks AVX2 where available.

#include "deepsea/runtime/snow_light.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "clones.h"
#include "deepsea/optics/lamp.h"
#include "deepsea/optics/phase.h"
#include "lamp_field_rows.h"

namespace deepsea {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// Adds lamp L's term for every particle to (r, g, b): with its Gaussian profile or with
/// profile 1 (theta kept for the caller), times the Henyey-Greenstein phase function of
/// asymmetry hg_g (isotropic: 0) or times 1 (cos psi kept for the caller).
template <bool Gaussian, bool RowPhase>
[[gnu::always_inline]] inline void lamp_particles(const Light& L, const Water& water, float hg_g,
                                                  const ParticleRows& p, float* __restrict r,
                                                  float* __restrict g, float* __restrict b,
                                                  float* __restrict theta_out,
                                                  float* __restrict cos_psi_out) {
    const int n = p.n;
    const Vec3T<float> pos{float(L.position.x), float(L.position.y), float(L.position.z)};
    const Vec3T<float> axis{float(L.direction.x), float(L.direction.y), float(L.direction.z)};
    const float sig = float(L.rid.sigma_deg * kDegToRad);
    const float cutoff = float(L.rid.cutoff_deg * kDegToRad);
    const float cr = float(water.c.r), cg = float(water.c.g), cb = float(water.c.b);
    const float ir = float(L.intensity.r), ig = float(L.intensity.g), ib = float(L.intensity.b);
    const float* __restrict px = p.x;
    const float* __restrict py = p.y;
    const float* __restrict pz = p.z;
    const float* __restrict pinv = p.inv_d2;
#pragma omp simd
    for (int q = 0; q < n; ++q) {
        // the equations are optics' (snow.h, lamp.h, phase.h); here only the row layout
        const ParticleGeometry<float> pg =
            particle_geometry<float>({px[q], py[q], pz[q]}, pinv[q], pos, axis);
        const float theta = lamp_angle(pg.cos_theta);
        float spread = lamp_spread(pg.d1, 1.0f);
        spread = theta > cutoff ? 0.0f : spread;
        if constexpr (RowPhase) {
            spread *= henyey_greenstein(hg_g, pg.cos_psi);
        } else {
            cos_psi_out[q] = pg.cos_psi;
        }
        if constexpr (Gaussian) {
            r[q] += gaussian_lamp_term(ir, theta, sig, spread, cr, pg.d1);
            g[q] += gaussian_lamp_term(ig, theta, sig, spread, cg, pg.d1);
            b[q] += gaussian_lamp_term(ib, theta, sig, spread, cb, pg.d1);
        } else {
            theta_out[q] = theta;
            r[q] += lamp_term(ir, 1.0f, spread, cr, pg.d1);
            g[q] += lamp_term(ig, 1.0f, spread, cg, pg.d1);
            b[q] += lamp_term(ib, 1.0f, spread, cb, pg.d1);
        }
    }
}

DEEPSEA_CLONES
void gaussian_hg(const Light& L, const Water& w, float hg_g, const ParticleRows& p, float* r,
                 float* g, float* b) {
    lamp_particles<true, true>(L, w, hg_g, p, r, g, b, nullptr, nullptr);
}

DEEPSEA_CLONES
void gaussian_kept_phase(const Light& L, const Water& w, const ParticleRows& p, float* r, float* g,
                         float* b, float* cos_psi) {
    lamp_particles<true, false>(L, w, 0.0f, p, r, g, b, nullptr, cos_psi);
}

DEEPSEA_CLONES
void unit_hg(const Light& L, const Water& w, float hg_g, const ParticleRows& p, float* r, float* g,
             float* b, float* theta) {
    lamp_particles<false, true>(L, w, hg_g, p, r, g, b, theta, nullptr);
}

DEEPSEA_CLONES
void unit_kept_phase(const Light& L, const Water& w, const ParticleRows& p, float* r, float* g,
                     float* b, float* theta, float* cos_psi) {
    lamp_particles<false, false>(L, w, 0.0f, p, r, g, b, theta, cos_psi);
}

/// Albedo, the water to the camera and the image's area in pixels.
DEEPSEA_CLONES
void finish(const Water& water, float albedo, float fxfy, const ParticleRows& p,
            float* __restrict er, float* __restrict eg, float* __restrict eb) {
    const float cr = float(water.c.r), cg = float(water.c.g), cb = float(water.c.b);
    const float k = float(M_PI * 0.25) * fxfy * albedo;
    const float* __restrict pz = p.z;
    const float* __restrict pinv = p.inv_d2;
    const float* __restrict pd = p.diameter;
    const int n = p.n;
#pragma omp simd
    for (int q = 0; q < n; ++q) {
        const float d2 = 1.0f / pinv[q];
        const float area = k * pd[q] * pd[q] * d2 / (pz[q] * pz[q] * pz[q]);
        er[q] *= area * transmission(cr, d2);
        eg[q] *= area * transmission(cg, d2);
        eb[q] *= area * transmission(cb, d2);
    }
}

/// Adds lamp L's scattered light (its field, optics' lamp_field_quadratic at each particle and
/// quadratic_in_scatter along the camera ray) to (r, g, b); tmp holds 3 kQuadraticCount n.
DEEPSEA_CLONES
void scattered_particles(const Light& L, const LampField& field, float k1, float k2,
                         const ParticleRows& p, float* __restrict tmp, float* __restrict r,
                         float* __restrict g, float* __restrict b) {
    const int n = p.n;
    const float ir = float(L.intensity.r), ig = float(L.intensity.g), ib = float(L.intensity.b);
    const float* __restrict px = p.x;
    const float* __restrict py = p.y;
    const float* __restrict pz = p.z;
    const float* __restrict pinv = p.inv_d2;
    lamp_field_rows(L, field, n, px, py, pz, tmp);
    const int stride = kQuadraticCount * n;
#pragma omp simd
    for (int q = 0; q < n; ++q) {
        const float vx = px[q] * pinv[q], vy = py[q] * pinv[q], vz = pz[q] * pinv[q];
        r[q] += ir * quadratic_in_scatter(tmp + q, n, k1, k2, vx, vy, vz);
        g[q] += ig * quadratic_in_scatter(tmp + stride + q, n, k1, k2, vx, vy, vz);
        b[q] += ib * quadratic_in_scatter(tmp + 2 * stride + q, n, k1, k2, vx, vy, vz);
    }
}

DEEPSEA_CLONES
void power_diameters(double ak, double span, double inv_k, double* __restrict q, int n) {
#pragma omp simd
    for (int i = 0; i < n; ++i) q[i] = std::pow(ak + q[i] * span, inv_k);
}

DEEPSEA_CLONES
void log_diameters(double a, double ratio, double* __restrict q, int n) {
#pragma omp simd
    for (int i = 0; i < n; ++i) q[i] = a * std::pow(ratio, q[i]);
}

}  // namespace

void snow_diameters(const SnowSizes& sizes, double* q, int n) {
    if (std::fabs(sizes.k()) < 1e-9)
        log_diameters(sizes.a(), sizes.b() / sizes.a(), q, n);
    else
        power_diameters(sizes.ak(), sizes.bk() - sizes.ak(), 1.0 / sizes.k(), q, n);
}

void snow_light(const Rig& rig, const Water& water, const Snow& snow, double fx, double fy,
                const ParticleRows& p, float* er, float* eg, float* eb, const SnowLightScratch& s,
                const std::vector<LampField>& scattered) {
    const int n = p.n;
    for (int q = 0; q < n; ++q) er[q] = eg[q] = eb[q] = 0.0f;
    const bool row_phase =
        snow.phase.kind == PhaseKind::Isotropic || snow.phase.kind == PhaseKind::HenyeyGreenstein;
    const float hg_g = snow.phase.kind == PhaseKind::HenyeyGreenstein ? float(snow.phase.g) : 0.0f;
    for (const Light& L : rig.lights) {
        const bool gaussian = L.rid.kind == Rid::Kind::Gaussian;
        if (gaussian && row_phase) {
            gaussian_hg(L, water, hg_g, p, er, eg, eb);
            continue;
        }
        // Per particle: the tabulated profile at theta, or the Petzold phase function.
        for (int q = 0; q < n; ++q) s.r[q] = s.g[q] = s.b[q] = 0.0f;
        if (gaussian)
            gaussian_kept_phase(L, water, p, s.r, s.g, s.b, s.cos_psi);
        else if (row_phase)
            unit_hg(L, water, hg_g, p, s.r, s.g, s.b, s.theta);
        else
            unit_kept_phase(L, water, p, s.r, s.g, s.b, s.theta, s.cos_psi);
        for (int q = 0; q < n; ++q) {
            double f = 1.0;
            if (!gaussian) f *= L.rid(double(s.theta[q]));
            if (!row_phase) f *= snow.phase(double(s.cos_psi[q]));
            er[q] += float(s.r[q] * f);
            eg[q] += float(s.g[q] * f);
            eb[q] += float(s.b[q] * f);
        }
    }
    if (!scattered.empty()) {
        if (scattered.size() != rig.lights.size())
            throw std::invalid_argument("snow_light: one lamp field per lamp");
        const float k1 = float(snow.phase.legendre_moment(1));
        const float k2 = float(snow.phase.legendre_moment(2));
        thread_local std::vector<float> tmp;
        tmp.resize(std::size_t(3) * kQuadraticCount * std::size_t(n));
        for (std::size_t l = 0; l < scattered.size(); ++l) {
            if (!scattered[l].empty())
                scattered_particles(rig.lights[l], scattered[l], k1, k2, p, tmp.data(), er, eg, eb);
        }
    }
    finish(water, float(snow.albedo), float(fx * fy), p, er, eg, eb);
}

}  // namespace deepsea
