// The port's rows' probes read each ray's 2 x 2 cell of the inverse depth in a pass of their own
// (docs/port-speed.md): with AVX2, two 8-byte loads a lane (a pixel pair of each row) and
// shuffles, instead of the four scalar loads and inserts a lane that GCC emulates a gather with.
// Loads only: every path gives the same floats (DEEPSEA_NO_CLONES builds the generic loop alone, as
// it does the runtime's clones).

#include "port_warp.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(DEEPSEA_NO_CLONES)
#define DEEPSEA_CELLS_AVX2
#include <immintrin.h>
#endif

namespace deepsea {

namespace {

void gather_cells_generic(int u, int n, const int* at, const float* inv, int W, float* c0,
                          float* c1, float* c2, float* c3) {
    for (; u < n; ++u) {
        const float* p = inv + at[u];
        c0[u] = p[0];
        c1[u] = p[1];
        c2[u] = p[W];
        c3[u] = p[W + 1];
    }
}

#ifdef DEEPSEA_CELLS_AVX2
/// Lanes i and j's pixel pairs of one row: (p[i], p[i + 1], p[j], p[j + 1]).
__attribute__((target("avx2"), always_inline)) inline __m128 pairs(const float* p, int i, int j) {
    const __m128 lo = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p + i)));
    return _mm_loadh_pi(lo, reinterpret_cast<const __m64*>(p + j));
}

/// Eight lanes' pairs of one row as the pairs' first and second pixels, lane by lane.
__attribute__((target("avx2"), always_inline)) inline void row8(const float* p, const int* a,
                                                                float* first, float* second) {
    // a = lanes 0 1 | 4 5 and b = 2 3 | 6 7, each lane's pair side by side: shuffling the
    // even and the odd floats of a and b gives lanes 0 1 2 3 | 4 5 6 7.
    const __m256 a01 = _mm256_set_m128(pairs(p, a[4], a[5]), pairs(p, a[0], a[1]));
    const __m256 a23 = _mm256_set_m128(pairs(p, a[6], a[7]), pairs(p, a[2], a[3]));
    _mm256_storeu_ps(first, _mm256_shuffle_ps(a01, a23, _MM_SHUFFLE(2, 0, 2, 0)));
    _mm256_storeu_ps(second, _mm256_shuffle_ps(a01, a23, _MM_SHUFFLE(3, 1, 3, 1)));
}

__attribute__((target("avx2"))) void gather_cells_avx2(int n, const int* at, const float* inv,
                                                       int W, float* c0, float* c1, float* c2,
                                                       float* c3) {
    int u = 0;
    for (; u + 8 <= n; u += 8) {
        row8(inv, at + u, c0 + u, c1 + u);
        row8(inv + W, at + u, c2 + u, c3 + u);
    }
    gather_cells_generic(u, n, at, inv, W, c0, c1, c2, c3);
}

const bool kHaveAvx2 = __builtin_cpu_supports("avx2");
#endif

}  // namespace

void gather_cells(int n, const int* at, const float* inv, int W, float* c0, float* c1, float* c2,
                  float* c3) {
#ifdef DEEPSEA_CELLS_AVX2
    if (kHaveAvx2) return gather_cells_avx2(n, at, inv, W, c0, c1, c2, c3);
#endif
    gather_cells_generic(0, n, at, inv, W, c0, c1, c2, c3);
}

}  // namespace deepsea
