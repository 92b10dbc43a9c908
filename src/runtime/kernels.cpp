#include "kernels.h"

#include <cmath>

#include "clones.h"

namespace deepsea::kernels {

DEEPSEA_CLONES
void shade_row(int n, const float* __restrict x, const float* __restrict y,
               const float* __restrict z, const float* __restrict e, const float* __restrict J,
               const float c[3], float* __restrict D, float* __restrict T,
               float* __restrict d2out) {
    const float inv_pi = float(1.0 / M_PI);
    const float cr = c[0], cg = c[1], cb = c[2];
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const float d2 = std::sqrt(x[u] * x[u] + y[u] * y[u] + z[u] * z[u]);
        const float surf = z[u] > 0.0f ? 1.0f : 0.0f;
        const float tr = surf * std::exp(-cr * d2);
        const float tg = surf * std::exp(-cg * d2);
        const float tb = surf * std::exp(-cb * d2);
        d2out[u] = d2;
        T[3 * u] = tr;
        T[3 * u + 1] = tg;
        T[3 * u + 2] = tb;
        D[3 * u] = J[3 * u] * inv_pi * e[u] * tr;
        D[3 * u + 1] = J[3 * u + 1] * inv_pi * e[n + u] * tg;
        D[3 * u + 2] = J[3 * u + 2] * inv_pi * e[2 * n + u] * tb;
    }
}

}  // namespace deepsea::kernels
