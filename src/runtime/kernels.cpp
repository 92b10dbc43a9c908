#include "kernels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "clones.h"
#include "deepsea/optics/forward.h"
#include "deepsea/optics/forward_lean.h"
#include "deepsea/optics/lamp.h"
#include "deepsea/optics/normals.h"

// The equations are optics' (lamp.h, transmission.h, forward.h, normals.h), shared with the
// exact reference; these loops add only the row layout and the open-water masks.

namespace deepsea::kernels {

DEEPSEA_CLONES
void shade_row(int n, const float* __restrict x, const float* __restrict y,
               const float* __restrict z, const float* __restrict e, const float* __restrict J,
               float* __restrict d2out, float* __restrict L) {
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float surf = z[u] > 0.0f ? 1.0f : 0.0f;
        d2out[u] = std::sqrt(x[u] * x[u] + y[u] * y[u] + z[u] * z[u]);
        L[3 * u] = surf * lambertian_radiance(J[3 * u], e[u]);
        L[3 * u + 1] = surf * lambertian_radiance(J[3 * u + 1], e[n + u]);
        L[3 * u + 2] = surf * lambertian_radiance(J[3 * u + 2], e[2 * n + u]);
    }
}

DEEPSEA_CLONES
void direct_row(int n, const float* __restrict d2, const float* __restrict c3,
                const float* __restrict L, float* __restrict dx, float* __restrict T,
                float* __restrict D, float* __restrict final) {
    // Every channel's distance where the rows hold its value, so that the loop below reads
    // and writes whole vectors (a loop over pixels stores three strided values a pixel).
    for (int u = 0; u < n; ++u) dx[3 * u] = dx[3 * u + 1] = dx[3 * u + 2] = d2[u];
    if (!T) {
        // only the image: D goes straight into it
#pragma omp simd
        for (int i = 0; i < 3 * n; ++i) {
            const float surf = dx[i] > 0.0f ? 1.0f : 0.0f;
            final[i] += direct_signal(L[i], surf * transmission<FastMath>(c3[i], dx[i]));
        }
        return;
    }
#pragma omp simd
    for (int i = 0; i < 3 * n; ++i) {
        const float surf = dx[i] > 0.0f ? 1.0f : 0.0f;
        T[i] = surf * transmission<FastMath>(c3[i], dx[i]);
        D[i] = direct_signal(L[i], T[i]);  // L is lambertian_radiance
        final[i] += D[i];
    }
}

DEEPSEA_CLONES
void forward_row(int n, const float* __restrict d2, const float c[3], const float G[3],
                 const float* __restrict blurred, float* __restrict F, float* __restrict final) {
    if (!G) {
        // The phase-function point spread: blurred is F itself (weighed before the blur).
#pragma omp simd
        for (int i = 0; i < 3 * n; ++i) {
            F[i] = blurred[i];
            final[i] += F[i];
        }
        return;
    }
    const float c0 = c[0], c1 = c[1], c2 = c[2];
    const float g0 = G[0], g1 = G[1], g2 = G[2];
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float d = d2[u];
        const float surf = d > 0.0f ? 1.0f : 0.0f;
        F[3 * u] = surf * forward_weight(g0, c0, d) * blurred[3 * u];
        F[3 * u + 1] = surf * forward_weight(g1, c1, d) * blurred[3 * u + 1];
        F[3 * u + 2] = surf * forward_weight(g2, c2, d) * blurred[3 * u + 2];
        final[3 * u] += F[3 * u];
        final[3 * u + 1] += F[3 * u + 1];
        final[3 * u + 2] += F[3 * u + 2];
    }
}

}  // namespace deepsea::kernels

namespace deepsea::kernels {

namespace {

/// has_surface(raw) ? raw : 0 on the float's bits: positive floats order as their bits, NaN
/// and inf lie above kFarDepth's, -0 and negative values below 1. (Under fast-math a float
/// comparison may assume that no NaN reaches it; this one cannot.)
[[gnu::always_inline]] inline float surface_depth(float raw, std::int32_t far_bits) {
    std::int32_t b;
    std::memcpy(&b, &raw, sizeof b);
    return (b > 0) & (b < far_bits) ? raw : 0.0f;
}

}  // namespace

DEEPSEA_CLONES
void geometry_row(int n, const float* __restrict rx, float ry_up, float ry, float ry_down,
                  const float* __restrict z_up, const float* __restrict raw,
                  const float* __restrict z_down, float* __restrict x, float* __restrict y,
                  float* __restrict z, float* __restrict nx, float* __restrict ny,
                  float* __restrict nz, unsigned char* __restrict irregular) {
    const float far = float(kFarDepth);
    std::int32_t far_bits;
    std::memcpy(&far_bits, &far, sizeof far_bits);
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float zs = surface_depth(raw[u], far_bits);
        x[u] = rx[u] * zs;
        y[u] = ry * zs;
        z[u] = zs;
    }
    if (!z_up || !z_down) {
        std::memset(irregular, 1, std::size_t(n));
        return;
    }
    irregular[0] = irregular[n - 1] = 1;
#pragma omp simd
    for (int u = 1; u < n - 1; ++u) {
        const float zc = z[u], zl = z[u - 1], zr = z[u + 1];
        const float zu = surface_depth(z_up[u], far_bits), zd = surface_depth(z_down[u], far_bits);
        const bool ok = zc > 0.0f && zl > 0.0f && zr > 0.0f && zu > 0.0f && zd > 0.0f &&
                        same_surface(zc, zl) && same_surface(zc, zr) && same_surface(zc, zu) &&
                        same_surface(zc, zd);
        // central differences, right - left and down - up, of back-projected neighbours
        // (passed as temporaries: see vec3t.h; not x and y above, whose differences GCC
        // rounds otherwise: it factors ry zr - ry zl)
        const Vec3T<float> nrm =
            normal_from_tangents(back_project(rx[u + 1], ry, zr) - back_project(rx[u - 1], ry, zl),
                                 back_project(rx[u], ry_down, zd) - back_project(rx[u], ry_up, zu),
                                 Vec3T<float>{rx[u], ry, 1.0f});
        nx[u] = nrm.x;
        ny[u] = nrm.y;
        nz[u] = nrm.z;
        irregular[u] = ok ? 0 : 1;
    }
}

}  // namespace deepsea::kernels

namespace deepsea::kernels {

DEEPSEA_CLONES
void lean_row(int n, const float* __restrict rx, float ry, const float* __restrict nx,
              const float* __restrict ny, const float* __restrict nz, float fx, float fy,
              float* __restrict lean) {
#pragma omp simd
    for (int u = 0; u < n; ++u)
        forward_lean(rx[u], ry, nx[u], ny[u], nz[u], fx, fy, lean[2 * u], lean[2 * u + 1]);
}

DEEPSEA_CLONES
float row_max(int n, const float* __restrict d) {
    // Eight lanes of maxima, then the lanes and the rest: the maximum is exact in any order
    // (an omp simd reduction stays scalar here, under -fno-associative-math).
    typedef float Lanes __attribute__((vector_size(32)));
    Lanes m = {};
    int u = 0;
    for (; u + 8 <= n; u += 8) {
        Lanes x;
        std::memcpy(&x, d + u, sizeof x);
        m = x > m ? x : m;
    }
    float r = 0.0f;
    for (int i = 0; i < 8; ++i) r = std::max(r, m[i]);
    for (; u < n; ++u) r = std::max(r, d[u]);
    return r;
}

DEEPSEA_CLONES
void add_scaled(int n, const float* __restrict s, const float* __restrict part,
                float* __restrict out, bool first) {
    // (a product, then a sum: no fused multiply-add here, as in the scalar loop this replaced)
    for (int c = 0; c < 3; ++c) {
        const float* __restrict p = part + std::size_t(c) * n;
        float* __restrict o = out + std::size_t(c) * n;
        if (first) {
#pragma omp simd
            for (int u = 0; u < n; ++u) o[u] = s[u] * p[u];
        } else {
#pragma omp simd
            for (int u = 0; u < n; ++u) o[u] += s[u] * p[u];
        }
    }
}

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
