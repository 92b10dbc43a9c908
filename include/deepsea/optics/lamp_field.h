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
    /// Coefficients odd in y (Y_1,-1, Y_2,-2, Y_2,-1) set to 0: the field at a node in the
    /// half-plane y = 0 is mirror-symmetric about it (the profile depends only on the angle to
    /// the axis), so they are 0 but for the estimate's noise, which, in a table shared by
    /// mirror-image lamps, would twist their light the same way.
    bool symmetric = false;
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

/// Coefficients per channel of the irradiance as a function of the surface normal n:
/// E(n) = k + b . n + n^T Q n (the order-2 SH irradiance written as a quadratic form), in the
/// order k, bx, by, bz, Qxx, Qyy, Qzz, Qxy, Qxz, Qyz.
inline constexpr int kQuadraticCount = 10;

/// The scattered irradiance of one lamp at point p (lamp frame: p . ex, p . ey, p . a) as a
/// function of the normal, per unit on-axis intensity: out[(c * kQuadraticCount + i) * stride]
/// for channel c and coefficient i, expressed in the frame whose axes ex, ey, a (the lamp's
/// frame vectors) are given in (the camera frame for the runtime; (1,0,0), (0,1,0), (0,0,1) for
/// the lamp frame itself). Bilinear in (log r, theta) between table nodes; zero beyond r_max.
/// The one home of this equation: lamp_field_irradiance evaluates it for one normal, the
/// runtime's rows (float, vectorised, `stride` apart so that a row of points writes planes)
/// interpolate it between points of a row.
template <typename T>
#if defined(__GNUC__)
__attribute__((always_inline))  // inside the runtime's `omp simd` loops: must inline to vectorise
#endif
inline void
lamp_field_quadratic(const LampFieldView<T>& f, T exx, T exy, T exz, T eyx, T eyy, T eyz, T ax,
                     T ay, T az, T px, T py, T pz, T* out, int stride) {
    using std::atan2;
    using std::log;
    using std::sqrt;
    const T rho = sqrt(px * px + py * py);
    const T r = sqrt(rho * rho + pz * pz);
    // The node half-plane's axes: radial e_r = ca ex + sa ey, azimuthal e_phi, and a.
    const T inv_rho = rho > T(0) ? T(1) / rho : T(0);
    const T ca = rho > T(0) ? px * inv_rho : T(1), sa = py * inv_rho;
    const T rx = ca * exx + sa * eyx, ry = ca * exy + sa * eyy, rz = ca * exz + sa * eyz;
    const T fx = -sa * exx + ca * eyx, fy = -sa * exy + ca * eyy, fz = -sa * exz + ca * eyz;
    T fi = (log(r > T(1e-30) ? r : T(1e-30)) - f.log_r0) * f.inv_log_step;
    fi = fi < T(0) ? T(0) : (fi > T(f.nr - 1) ? T(f.nr - 1) : fi);
    T fj = atan2(rho, pz) * f.theta_scale;
    fj = fj > T(f.ntheta - 1) ? T(f.ntheta - 1) : fj;
    const int i0 = int(fi) < f.nr - 1 ? int(fi) : f.nr - 2;
    const int j0 = int(fj) < f.ntheta - 1 ? int(fj) : f.ntheta - 2;
    const T wi = fi - T(i0), wj = fj - T(j0);
    const T inside = r > f.r_max ? T(0) : T(1);
    const T w[4] = {inside * (T(1) - wi) * (T(1) - wj), inside * (T(1) - wi) * wj,
                    inside * wi * (T(1) - wj), inside * wi * wj};
    const int node[4] = {i0 * f.ntheta + j0, i0 * f.ntheta + j0 + 1, (i0 + 1) * f.ntheta + j0,
                         (i0 + 1) * f.ntheta + j0 + 1};
    // SH basis constants times the clamped cosine's A_l (sh_basis, sh_cosine_factor).
    const T c0 = T(3.141592653589793 * 0.282094791773878);
    const T c1 = T(2.094395102393195 * 0.488602511902920);
    const T c2 = T(0.785398163397448 * 1.092548430592079);
    const T c6 = T(0.785398163397448 * 0.315391565252520);
    const T c8 = T(0.785398163397448 * 0.546274215296040);
#pragma GCC unroll 3
    for (int c = 0; c < 3; ++c) {
        T L[kShCount];
#pragma GCC unroll 9
        for (int m = 0; m < kShCount; ++m) {
            // int offsets: gathers vectorise; fully unrolled: no control flow in the row loop
            L[m] = w[0] * T(f.sh[node[0] * (kShCount * 3) + 3 * m + c]) +
                   w[1] * T(f.sh[node[1] * (kShCount * 3) + 3 * m + c]) +
                   w[2] * T(f.sh[node[2] * (kShCount * 3) + 3 * m + c]) +
                   w[3] * T(f.sh[node[3] * (kShCount * 3) + 3 * m + c]);
        }
        // In the half-plane frame (x = e_r, y = e_phi, z = a): E = k + b . m + m^T Q m.
        const T k = c0 * L[0] - c6 * L[6];
        const T bx = c1 * L[3], by = c1 * L[1], bz = c1 * L[2];
        const T qxx = c8 * L[8], qyy = -c8 * L[8], qzz = T(3) * c6 * L[6];
        const T qxy = T(0.5) * c2 * L[4], qyz = T(0.5) * c2 * L[5], qxz = T(0.5) * c2 * L[7];
        // Into the output frame: b' = R b, Q' = R Q R^T with R's columns e_r, e_phi, a.
        T* o = out + c * kQuadraticCount * stride;
        o[0] = k;
        o[1 * stride] = rx * bx + fx * by + ax * bz;
        o[2 * stride] = ry * bx + fy * by + ay * bz;
        o[3 * stride] = rz * bx + fz * by + az * bz;
        // (R Q) rows, then times R^T columns
        const T ax0 = rx * qxx + fx * qxy + ax * qxz, ax1 = rx * qxy + fx * qyy + ax * qyz,
                ax2 = rx * qxz + fx * qyz + ax * qzz;
        const T ay0 = ry * qxx + fy * qxy + ay * qxz, ay1 = ry * qxy + fy * qyy + ay * qyz,
                ay2 = ry * qxz + fy * qyz + ay * qzz;
        const T az0 = rz * qxx + fz * qxy + az * qxz, az1 = rz * qxy + fz * qyy + az * qyz,
                az2 = rz * qxz + fz * qyz + az * qzz;
        o[4 * stride] = ax0 * rx + ax1 * fx + ax2 * ax;
        o[5 * stride] = ay0 * ry + ay1 * fy + ay2 * ay;
        o[6 * stride] = az0 * rz + az1 * fz + az2 * az;
        o[7 * stride] = ax0 * ry + ax1 * fy + ax2 * ay;
        o[8 * stride] = ax0 * rz + ax1 * fz + ax2 * az;
        o[9 * stride] = ay0 * rz + ay1 * fz + ay2 * az;
    }
}

/// E(n) from one channel's quadratic-form coefficients q[i * stride] (kQuadraticCount), for a
/// unit normal n.
template <typename T>
inline T quadratic_irradiance(const T* q, int stride, T nx, T ny, T nz) {
    return q[0] + q[stride] * nx + q[2 * stride] * ny + q[3 * stride] * nz +
           q[4 * stride] * nx * nx + q[5 * stride] * ny * ny + q[6 * stride] * nz * nz +
           T(2) * (q[7 * stride] * nx * ny + q[8 * stride] * nx * nz + q[9 * stride] * ny * nz);
}

/// Radiance a small particle scatters from the lamp's scattered light, per unit albedo: the
/// integral of L(d) p(psi) over incident directions d, for one channel's quadratic-form
/// coefficients q[i * stride] (lamp_field_quadratic's) and the unit vector (vx, vy, vz) from
/// the camera through the particle (the direction light must come from to be scattered
/// straight on toward the camera). The form splits into the radiance's bands: l = 0 is
/// k + tr(Q) / 3 (= pi L_00 Y_00), l = 1 is b . v (= 2 pi / 3 sum L_1m Y_1m(v)), l = 2 is
/// v^T Q v - tr(Q) / 3 (= pi / 4 sum L_2m Y_2m(v)); dividing out the clamped cosine's A_l and
/// multiplying by the phase function's Legendre moments k1, k2 (Phase::legendre_moment) gives
/// sum_l k_l sum_m L_lm Y_lm(v) (Funk-Hecke). Clamped at 0 like the irradiance.
template <typename T>
inline T quadratic_in_scatter(const T* q, int stride, T k1, T k2, T vx, T vy, T vz) {
    const T tr3 = (q[4 * stride] + q[5 * stride] + q[6 * stride]) * T(1.0 / 3.0);
    const T band0 = q[0] + tr3;
    const T band1 = q[stride] * vx + q[2 * stride] * vy + q[3 * stride] * vz;
    const T band2 =
        q[4 * stride] * vx * vx + q[5 * stride] * vy * vy + q[6 * stride] * vz * vz +
        T(2) * (q[7 * stride] * vx * vy + q[8 * stride] * vx * vz + q[9 * stride] * vy * vz) - tr3;
    const T s = band0 * T(1.0 / M_PI) + band1 * (k1 * T(1.5 / M_PI)) + band2 * (k2 * T(4.0 / M_PI));
    return s > T(0) ? s : T(0);
}

/// Scattered irradiance (per unit on-axis intensity, per channel) onto a Lambertian surface at
/// point p with unit normal n, both in the lamp frame, into (er, eg, eb): lamp_field_quadratic
/// evaluated at n, clamped at 0 (order-2 ringing can dip below 0 facing away from the light).
template <typename T>
inline void lamp_field_irradiance(const LampFieldView<T>& f, T px, T py, T pz, T nx, T ny, T nz,
                                  T& er, T& eg, T& eb) {
    T q[3 * kQuadraticCount];
    lamp_field_quadratic(f, T(1), T(0), T(0), T(0), T(1), T(0), T(0), T(0), T(1), px, py, pz, q, 1);
    const T e[3] = {quadratic_irradiance(q, 1, nx, ny, nz),
                    quadratic_irradiance(q + kQuadraticCount, 1, nx, ny, nz),
                    quadratic_irradiance(q + 2 * kQuadraticCount, 1, nx, ny, nz)};
    er = e[0] > T(0) ? e[0] : T(0);
    eg = e[1] > T(0) ? e[1] : T(0);
    eb = e[2] > T(0) ? e[2] : T(0);
}

}  // namespace deepsea
