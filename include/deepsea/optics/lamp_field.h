#pragma once
/// \file The scattered light around one lamp (docs/model.md, "Multiple scattering"): how much
/// lamp light reaches a surface after scattering in the water, all orders. A lamp's intensity
/// depends only on the angle to its axis, so in water without walls this light is symmetric
/// about the axis: a table over distance r and polar angle theta in the lamp's own frame holds
/// all of it, whatever the camera. Each node holds the order-2 spherical harmonics of the
/// radiance arriving there (9 per channel), enough for the irradiance onto any tilted
/// Lambertian surface (truncation error measured in docs/model.md).

#include <cmath>
#include <cstdint>
#include <vector>

#include "deepsea/core/parallel.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/spherical_harmonics.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// The table, per unit on-axis intensity in every channel. Lamp frame: origin at the lamp,
/// z along its axis, x and y any perpendicular pair (lamp_frame); nodes lie in the half-plane
/// y = 0, x >= 0: r_i = r0 (r_max / r0)^(i / (nr - 1)), theta_j = pi j / (ntheta - 1).
struct LampField {
    int nr = 0, ntheta = 0;
    double r0 = 0.0, r_max = 0.0;  ///< metres
    std::vector<float> sh;         ///< [((i * ntheta + j) * kShCount + m) * 3 + c]
    double rel_std_error = 0.0;    ///< Monte Carlo: mean standard error of the irradiance
                                   ///< facing the lamp / that irradiance, over the nodes

    bool empty() const { return sh.empty(); }
    std::size_t size() const { return std::size_t(nr) * ntheta * kShCount * 3; }
};

/// Monte Carlo settings of a lamp field.
struct LampFieldSettings {
    int nr = 40, ntheta = 37;
    double r0 = 0.02;     ///< metres; nearer points use the r0 values
    double r_max = 30.0;  ///< metres; farther points get no scattered light
    int samples = 4096;   ///< directions per node
    std::uint64_t seed = 1;
};

/// Bakes the field of one lamp (its RID; position, axis and intensity do not matter) in this
/// water. Parallel over nodes, identical at any thread count.
LampField bake_lamp_field(const Light& lamp, const Water& water, const LampFieldSettings& s,
                          const Parallel& par = {});

/// Unit vectors (x, y) completing a lamp's axis a to a right-handed frame (x, y, a).
void lamp_frame(const Vec3& a, Vec3& x, Vec3& y);

/// A LampField's constants in the number type of a row loop (computed once, not per pixel).
template <typename T>
struct LampFieldView {
    const float* sh = nullptr;
    int nr = 0, ntheta = 0;
    T log_r0 = 0, inv_log_step = 0, theta_scale = 0, r_max = 0;

    explicit LampFieldView(const LampField& f)
        : sh(f.sh.data()),
          nr(f.nr),
          ntheta(f.ntheta),
          log_r0(T(std::log(f.r0))),
          inv_log_step(T((f.nr - 1) / std::log(f.r_max / f.r0))),
          theta_scale(T((f.ntheta - 1) / M_PI)),
          r_max(T(f.r_max)) {}
};

/// Scattered irradiance (per unit on-axis intensity, per channel) onto a Lambertian surface at
/// point p with unit normal n, both in the lamp frame, into (er, eg, eb). Bilinear in (log r,
/// theta) between nodes; zero beyond r_max. The one home of this equation: the baker's checks
/// (double) and the runtime's rows (float, vectorised) call it.
template <typename T>
inline void lamp_field_irradiance(const LampFieldView<T>& f, T px, T py, T pz, T nx, T ny, T nz,
                                  T& er, T& eg, T& eb) {
    using std::atan2;
    using std::log;
    using std::sqrt;
    const T rho = sqrt(px * px + py * py);
    const T r = sqrt(rho * rho + pz * pz);
    // Rotate the normal about the axis into the node half-plane (azimuth of p to 0).
    const T inv_rho = rho > T(0) ? T(1) / rho : T(0);
    const T ca = rho > T(0) ? px * inv_rho : T(1), sa = py * inv_rho;
    const T mx = ca * nx + sa * ny, my = -sa * nx + ca * ny;
    T Y[kShCount];
    sh_basis(mx, my, nz, Y);
#pragma GCC unroll 9
    for (int m = 0; m < kShCount; ++m) Y[m] *= sh_cosine_factor<T>(m);
    T fi = (log(r > T(1e-30) ? r : T(1e-30)) - f.log_r0) * f.inv_log_step;
    fi = fi < T(0) ? T(0) : (fi > T(f.nr - 1) ? T(f.nr - 1) : fi);
    T fj = atan2(rho, pz) * f.theta_scale;
    fj = fj > T(f.ntheta - 1) ? T(f.ntheta - 1) : fj;
    const int i0 = int(fi) < f.nr - 1 ? int(fi) : f.nr - 2;
    const int j0 = int(fj) < f.ntheta - 1 ? int(fj) : f.ntheta - 2;
    const T wi = fi - T(i0), wj = fj - T(j0);
    const T w[4] = {(T(1) - wi) * (T(1) - wj), (T(1) - wi) * wj, wi * (T(1) - wj), wi * wj};
    const int node[4] = {i0 * f.ntheta + j0, i0 * f.ntheta + j0 + 1, (i0 + 1) * f.ntheta + j0,
                         (i0 + 1) * f.ntheta + j0 + 1};
    T acc0 = T(0), acc1 = T(0), acc2 = T(0);
    // Fully unrolled, so that the caller's `omp simd` row loop has no inner control flow.
#pragma GCC unroll 4
    for (int q = 0; q < 4; ++q) {
        const int base = node[q] * (kShCount * 3);  // int offsets: gathers vectorise
#pragma GCC unroll 9
        for (int m = 0; m < kShCount; ++m) {
            const T a = w[q] * Y[m];
            acc0 += a * T(f.sh[base + 3 * m]);
            acc1 += a * T(f.sh[base + 3 * m + 1]);
            acc2 += a * T(f.sh[base + 3 * m + 2]);
        }
    }
    // Order-2 ringing can dip below 0 facing away from the light.
    const T inside = r > f.r_max ? T(0) : T(1);
    er = inside * (acc0 > T(0) ? acc0 : T(0));
    eg = inside * (acc1 > T(0) ? acc1 : T(0));
    eb = inside * (acc2 > T(0) ? acc2 : T(0));
}

}  // namespace deepsea
