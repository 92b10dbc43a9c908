#include "kernels.h"

#include <cmath>

#include "clones.h"

namespace deepsea::kernels {

DEEPSEA_CLONES
void shade_row(int n, const float* __restrict x, const float* __restrict y,
               const float* __restrict z, const float* __restrict e, const float* __restrict J,
               const float c[3], float* __restrict D, float* __restrict d2out) {
    const float inv_pi = float(1.0 / M_PI);
    const float cr = c[0], cg = c[1], cb = c[2];
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float d2 = std::sqrt(x[u] * x[u] + y[u] * y[u] + z[u] * z[u]);
        const float surf = z[u] > 0.0f ? inv_pi : 0.0f;
        d2out[u] = d2;
        D[3 * u] = J[3 * u] * surf * e[u] * std::exp(-cr * d2);
        D[3 * u + 1] = J[3 * u + 1] * surf * e[n + u] * std::exp(-cg * d2);
        D[3 * u + 2] = J[3 * u + 2] * surf * e[2 * n + u] * std::exp(-cb * d2);
    }
}

}  // namespace deepsea::kernels

namespace deepsea::kernels {

DEEPSEA_CLONES
void finish_row(int n, const float* __restrict d2, const float c[3], const float G[3],
                const float* __restrict blurred, const float* __restrict D,
                float* __restrict T, float* __restrict F, float* __restrict final) {
    const float c0 = c[0], c1 = c[1], c2 = c[2];
    if (!blurred) {
#pragma omp simd
        for (int u = 0; u < n; ++u) {
            const float surf = d2[u] > 0.0f ? 1.0f : 0.0f;
            T[3 * u] = surf * std::exp(-c0 * d2[u]);
            T[3 * u + 1] = surf * std::exp(-c1 * d2[u]);
            T[3 * u + 2] = surf * std::exp(-c2 * d2[u]);
        }
#pragma omp simd
        for (int i = 0; i < 3 * n; ++i) {
            F[i] = 0.0f;
            final[i] += D[i];
        }
        return;
    }
    const float g0 = G[0], g1 = G[1], g2 = G[2];
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float d = d2[u];
        const float surf = d > 0.0f ? 1.0f : 0.0f;
        const float t0 = surf * std::exp(-c0 * d);
        const float t1 = surf * std::exp(-c1 * d);
        const float t2 = surf * std::exp(-c2 * d);
        T[3 * u] = t0;
        T[3 * u + 1] = t1;
        T[3 * u + 2] = t2;
        F[3 * u] = surf * (std::exp(-g0 * d) - t0) * blurred[3 * u];
        F[3 * u + 1] = surf * (std::exp(-g1 * d) - t1) * blurred[3 * u + 1];
        F[3 * u + 2] = surf * (std::exp(-g2 * d) - t2) * blurred[3 * u + 2];
        final[3 * u] += D[3 * u] + F[3 * u];
        final[3 * u + 1] += D[3 * u + 1] + F[3 * u + 1];
        final[3 * u + 2] += D[3 * u + 2] + F[3 * u + 2];
    }
}

}  // namespace deepsea::kernels

namespace deepsea::kernels {

DEEPSEA_CLONES
void normals_row(int n, const float* __restrict rx, float ry_up, float ry, float ry_down,
                 const float* __restrict z_up, const float* __restrict z,
                 const float* __restrict z_down, float disc, float* __restrict nx,
                 float* __restrict ny, float* __restrict nz, unsigned char* __restrict irregular) {
    irregular[0] = irregular[n - 1] = 1;
#pragma omp simd
    for (int u = 1; u < n - 1; ++u) {
        const float zc = z[u], zl = z[u - 1], zr = z[u + 1], zu = z_up[u], zd = z_down[u];
        const float lim = disc * zc;
        const bool ok = zc > 0.0f && zl > 0.0f && zr > 0.0f && zu > 0.0f && zd > 0.0f &&
                        std::fabs(zl - zc) <= lim && std::fabs(zr - zc) <= lim &&
                        std::fabs(zu - zc) <= lim && std::fabs(zd - zc) <= lim;
        // tangents: right - left and down - up, back-projected
        const float ax = rx[u + 1] * zr - rx[u - 1] * zl, ay = ry * (zr - zl), az = zr - zl;
        const float bx = rx[u] * (zd - zu), by = ry_down * zd - ry_up * zu, bz = zd - zu;
        float cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
        const float inv = 1.0f / std::sqrt(cx * cx + cy * cy + cz * cz + 1e-30f);
        // face the camera: n . P < 0 with P = (rx z, ry z, z)
        const float s = (cx * rx[u] + cy * ry + cz) > 0.0f ? -inv : inv;
        nx[u] = cx * s;
        ny[u] = cy * s;
        nz[u] = cz * s;
        irregular[u] = ok ? 0 : 1;
    }
}

}  // namespace deepsea::kernels

namespace deepsea::kernels {

DEEPSEA_CLONES
void interleave(int n, const float* __restrict planes, float* __restrict rgb) {
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        rgb[3 * u] = planes[u];
        rgb[3 * u + 1] = planes[n + u];
        rgb[3 * u + 2] = planes[2 * n + u];
    }
}

}  // namespace deepsea::kernels
