// Hot loop: compiled with -ffast-math -fopenmp-simd (see CMakeLists.txt); slabs and weights
// come from depth_cells (depth_slabs.h).

#include "backscatter_lookup.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "clones.h"
#include "float4.h"

// (the Float8 values live in registers inside the clones, the helpers inlined: no call passes
// one, so GCC's note that AVX changes the ABI of such calls does not apply to the generic clone)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace deepsea {

namespace {

/// a + w (b - a) lane by lane: lattice.h's lerp.
[[gnu::always_inline]] inline Float8 lerp8(Float8 a, Float8 b, Float8 w) { return a + w * (b - a); }
[[gnu::always_inline]] inline Float4 lerp4(Float4 a, Float4 b, Float4 w) { return a + w * (b - a); }

[[gnu::always_inline]] inline Float8 cat(Float4 a, Float4 b) {
    return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
}

/// Pixels u and u + 1 as [R G B - | R G B -].
[[gnu::always_inline]] inline Float8 pair(int u, const float* __restrict slice,
                                          const int* __restrict col0, const int* __restrict col1,
                                          const float* __restrict colw, const int* __restrict slab,
                                          const float* __restrict wzs) {
    const float* p0 = slice + col0[u] + 3 * slab[u];
    const float* p1 = slice + col1[u] + 3 * slab[u];
    const float* q0 = slice + col0[u + 1] + 3 * slab[u + 1];
    const float* q1 = slice + col1[u + 1] + 3 * slab[u + 1];
    const Float8 wz = cat(splat(wzs[u]), splat(wzs[u + 1]));
    const Float8 cw = cat(splat(colw[u]), splat(colw[u + 1]));
    return lerp8(lerp8(cat(load4(p0), load4(q0)), cat(load4(p0 + 3), load4(q0 + 3)), wz),
                 lerp8(cat(load4(p1), load4(q1)), cat(load4(p1 + 3), load4(q1 + 3)), wz), cw);
}

/// Pixels u .. u + 3: two pairs, their twelve values stored as two whole vectors.
[[gnu::always_inline]] inline void quad(int u, const float* __restrict slice,
                                        const int* __restrict col0, const int* __restrict col1,
                                        const float* __restrict colw, const int* __restrict slab,
                                        const float* __restrict wzs, float* __restrict out) {
    const Float8 a = pair(u, slice, col0, col1, colw, slab, wzs);
    const Float8 b = pair(u + 2, slice, col0, col1, colw, slab, wzs);
    float* o = out + 3 * std::size_t(u);
    const Float8 head = __builtin_shufflevector(a, b, 0, 1, 2, 4, 5, 6, 8, 9);
    const Float4 tail = __builtin_shufflevector(b, b, 2, 4, 5, 6);
    std::memcpy(o, &head, sizeof head);
    store4(o + 8, tail);
}

/// Pixel u alone.
[[gnu::always_inline]] inline void single(int u, const float* __restrict slice,
                                          const int* __restrict col0, const int* __restrict col1,
                                          const float* __restrict colw, const int* __restrict slab,
                                          const float* __restrict wzs, float* __restrict out) {
    const int k = slab[u];
    const Float4 wz = splat(wzs[u]);
    const float* p0 = slice + col0[u] + 3 * k;
    const float* p1 = slice + col1[u] + 3 * k;
    const Float4 b = lerp4(lerp4(load4(p0), load4(p0 + 3), wz), lerp4(load4(p1), load4(p1 + 3), wz),
                           splat(colw[u]));
    out[3 * u] = b[0];
    out[3 * u + 1] = b[1];
    out[3 * u + 2] = b[2];
}

/// Eight pixels' 24 interleaved values as three vectors: vector q, lane l holds value 8 q + l,
/// pixel (8 q + l) / 3, channel (8 q + l) % 3. A value a pixel, x[0 .. 7], spread so:
template <int q>
[[gnu::always_inline]] inline Float8 by_pixel(Float8 x) {
    if constexpr (q == 0) return __builtin_shufflevector(x, x, 0, 0, 0, 1, 1, 1, 2, 2);
    if constexpr (q == 1) return __builtin_shufflevector(x, x, 2, 3, 3, 3, 4, 4, 4, 5);
    return __builtin_shufflevector(x, x, 5, 5, 6, 6, 6, 7, 7, 7);
}
/// and a sample's three channels [R G B -] so:
template <int q>
[[gnu::always_inline]] inline Float8 by_channel(Float4 x) {
    if constexpr (q == 0) return __builtin_shufflevector(x, x, 0, 1, 2, 0, 1, 2, 0, 1);
    if constexpr (q == 1) return __builtin_shufflevector(x, x, 2, 0, 1, 2, 0, 1, 2, 0);
    return __builtin_shufflevector(x, x, 1, 2, 0, 1, 2, 0, 1, 2);
}

/// Whether slab[u .. u + 7] all equal k (two ints a 64-bit word).
[[gnu::always_inline]] inline bool one_slab(const int* slab, int k) {
    std::uint64_t w0, w1, w2, w3;
    std::memcpy(&w0, slab, sizeof w0);
    std::memcpy(&w1, slab + 2, sizeof w1);
    std::memcpy(&w2, slab + 4, sizeof w2);
    std::memcpy(&w3, slab + 6, sizeof w3);
    const std::uint64_t kk = std::uint64_t(std::uint32_t(k)) * 0x100000001ull;
    return ((w0 ^ kk) | (w1 ^ kk) | (w2 ^ kk) | (w3 ^ kk)) == 0;
}

}  // namespace

DEEPSEA_CLONES
void lookup_row_pairs(int n, const float* __restrict slice, const int* __restrict col0,
                      const int* __restrict col1, const float* __restrict colw,
                      const int* __restrict slab, const float* __restrict wzs,
                      float* __restrict out) {
    int u = 0;
    for (; u + 4 <= n; u += 4) quad(u, slice, col0, col1, colw, slab, wzs, out);
    for (; u < n; ++u) single(u, slice, col0, col1, colw, slab, wzs, out);
}

DEEPSEA_CLONES
void lookup_row(int n, const float* __restrict slice, const LookupColumns& cols,
                const int* __restrict slab, const float* __restrict wzs, float* __restrict out) {
    const int* __restrict col0 = cols.col0;
    const int* __restrict col1 = cols.col1;
    const float* __restrict colw = cols.colw;
    // The span's two columns' samples at slab kc, laid out as the values (by_channel):
    // a = S[k], d = S[k + 1] - S[k], for the first column (0) and the second (1).
    Float8 a0[3] = {}, d0[3] = {}, a1[3] = {}, d1[3] = {};
    int u = 0;
    for (int s = 0; s < cols.spans && u < n; ++s) {
        const int end = cols.span_end[s] < n ? cols.span_end[s] : n;
        int kc = -1;
        for (; u + 8 <= end; u += 8) {
            const int k = slab[u];
            if (!one_slab(slab + u, k)) {
                quad(u, slice, col0, col1, colw, slab, wzs, out);
                quad(u + 4, slice, col0, col1, colw, slab, wzs, out);
                continue;
            }
            if (k != kc) {
                kc = k;
                const float* p0 = slice + col0[u] + 3 * k;
                const float* p1 = slice + col1[u] + 3 * k;
                const Float4 s0 = load4(p0), t0 = load4(p0 + 3) - s0;
                const Float4 s1 = load4(p1), t1 = load4(p1 + 3) - s1;
                a0[0] = by_channel<0>(s0), a0[1] = by_channel<1>(s0), a0[2] = by_channel<2>(s0);
                d0[0] = by_channel<0>(t0), d0[1] = by_channel<1>(t0), d0[2] = by_channel<2>(t0);
                a1[0] = by_channel<0>(s1), a1[1] = by_channel<1>(s1), a1[2] = by_channel<2>(s1);
                d1[0] = by_channel<0>(t1), d1[1] = by_channel<1>(t1), d1[2] = by_channel<2>(t1);
            }
            const Float8 wz = load8(wzs + u), cw = load8(colw + u);
            float* o = out + 3 * std::size_t(u);
            const auto values = [&](auto q, Float8 w, Float8 c) {
                const Float8 x0 = a0[q] + w * d0[q], x1 = a1[q] + w * d1[q];
                const Float8 b = x0 + c * (x1 - x0);
                std::memcpy(o + 8 * q, &b, sizeof b);
            };
            values(std::integral_constant<int, 0>{}, by_pixel<0>(wz), by_pixel<0>(cw));
            values(std::integral_constant<int, 1>{}, by_pixel<1>(wz), by_pixel<1>(cw));
            values(std::integral_constant<int, 2>{}, by_pixel<2>(wz), by_pixel<2>(cw));
        }
        for (; u + 4 <= end; u += 4) quad(u, slice, col0, col1, colw, slab, wzs, out);
        for (; u < end; ++u) single(u, slice, col0, col1, colw, slab, wzs, out);
    }
    lookup_row_pairs(n - u, slice, col0 + u, col1 + u, colw + u, slab + u, wzs + u, out + 3 * u);
}

}  // namespace deepsea
