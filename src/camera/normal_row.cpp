// Rows of standard normal deviates (noise.h's normal_from_bits): the one generator of the
// camera's fixed patterns and temporal noise. With AVX2 and FMA, 8 values at a time: the hash,
// t's octave and mantissa from the float of 2 i + 1, and the octave table's five coefficients
// read with vpermps (one instruction each: the table has 8 octaves); the 0.39 % of values below
// the table (Giles' erfinv) gathered and computed 8 at a time afterwards.

#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "rows.h"

namespace deepsea::camera_rows {

namespace {

#if defined(__x86_64__) && defined(__GNUC__)
/// A stream's deviates from a counter on, 8 at a time: the scrambled counters and constants.
struct Normal8 {
    __m256i scrambled, stride, h1, h2, h3, lsb, low24, low23, one, sign;
    __m256 mid, below, c[5];
};

/// The deviates of stream `key` from noise counter `base` on.
__attribute__((target("avx2,fma"))) inline Normal8 normal8_start(NoiseKey key, std::uint32_t base) {
    Normal8 s;
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    // The scrambled counters counter * mul + add (mod 2^32) of 8 values, stepped by 8 mul: one
    // add per 8 values instead of a broadcast, a multiply and an add.
    s.scrambled = _mm256_add_epi32(
        _mm256_mullo_epi32(_mm256_add_epi32(_mm256_set1_epi32(std::int32_t(base)), lanes),
                           _mm256_set1_epi32(std::int32_t(key.mul))),
        _mm256_set1_epi32(std::int32_t(key.add)));
    s.stride = _mm256_set1_epi32(std::int32_t(8u * key.mul));
    s.h1 = _mm256_set1_epi32(std::int32_t(0xed5ad4bbu));
    s.h2 = _mm256_set1_epi32(std::int32_t(0xac4c1b51u));
    s.h3 = _mm256_set1_epi32(std::int32_t(0x31848babu));
    s.lsb = _mm256_set1_epi32(1);
    s.low24 = _mm256_set1_epi32(0xffffff);
    s.low23 = _mm256_set1_epi32(0x7fffff);
    s.one = _mm256_set1_epi32(0x3f800000);
    s.sign = _mm256_set1_epi32(std::int32_t(0x80000000u));
    s.mid = _mm256_set1_ps(1.5f);
    s.below = _mm256_set1_ps(65536.0f);  // below the table: t < 2^-9, 2 i + 1 < 2^16
    // The table's octave j = 150 - e for the float of 2 i + 1 of exponent e (143 to 150);
    // vpermps reads an index's low 3 bits, so the table is stored by e mod 8: entry e & 7
    // holds octave (6 - (e & 7)) mod 8.
    for (int k = 0; k < 5; ++k) {
        alignas(32) float by_e[8];
        for (int j = 0; j < 8; ++j) by_e[j] = kNormalTable[k][(6 - j) & 7];
        s.c[k] = _mm256_load_ps(by_e);
    }
    return s;
}

/// The next 8 deviates; `tail` gets a bit per lane below the table (its value is not the
/// deviate: normal_tails gives it).
__attribute__((target("avx2,fma"), always_inline)) inline __m256 normal8_next(Normal8& s,
                                                                              int& tail) {
    __m256i x = s.scrambled;  // triple32
    s.scrambled = _mm256_add_epi32(s.scrambled, s.stride);
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 17));
    x = _mm256_mullo_epi32(x, s.h1);
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 11));
    x = _mm256_mullo_epi32(x, s.h2);
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
    x = _mm256_mullo_epi32(x, s.h3);
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 14));
    // t = (2 i + 1) / 2^25, i = bits 8-30: the float of 2 i + 1 (exact, below 2^24) has t's
    // mantissa, and its exponent is t's + 25.
    const __m256i odd = _mm256_and_si256(_mm256_or_si256(_mm256_srli_epi32(x, 7), s.lsb), s.low24);
    const __m256 f = _mm256_cvtepi32_ps(odd);
    const __m256i tb = _mm256_castps_si256(f), e = _mm256_srli_epi32(tb, 23);
    const __m256 y = _mm256_sub_ps(
        _mm256_castsi256_ps(_mm256_or_si256(_mm256_and_si256(tb, s.low23), s.one)), s.mid);
    __m256 p = _mm256_permutevar8x32_ps(s.c[4], e);
    for (int k = 3; k >= 0; --k) p = _mm256_fmadd_ps(p, y, _mm256_permutevar8x32_ps(s.c[k], e));
    tail = _mm256_movemask_ps(_mm256_cmp_ps(f, s.below, _CMP_LT_OS));
    return _mm256_xor_ps(p, _mm256_castsi256_ps(_mm256_and_si256(x, s.sign)));
}

/// The m values below the table listed in `index` (counters base + index[j]) in a vector
/// loop, into z[index[j]]. `tz`: scratch for m floats.
[[gnu::always_inline]] inline void normal_tails(NoiseKey key, std::uint32_t base, int m,
                                                const std::int32_t* index, float* tz, float* z) {
#pragma omp simd
    for (int j = 0; j < m; ++j)
        tz[j] = normal_tail_from_bits<float>(noise_bits(key, base + std::uint32_t(index[j])));
    for (int j = 0; j < m; ++j) z[index[j]] = tz[j];
}

__attribute__((target("avx2,fma"))) void normal_row_avx2(NoiseKey key, std::uint32_t base, int n,
                                                         float* z, std::int32_t* index) {
    Normal8 s = normal8_start(key, base);
    int m = 0, i = 0;
    for (; i + 8 <= n; i += 8) {
        int tail;
        _mm256_storeu_ps(z + i, normal8_next(s, tail));
        while (tail) {  // rare: 3 % of groups of 8
            index[m++] = i + __builtin_ctz(unsigned(tail));
            tail &= tail - 1;
        }
    }
    for (; i < n; ++i) z[i] = normal_from_bits<float>(noise_bits(key, base + std::uint32_t(i)));
    float tz[8];
    for (int j0 = 0; j0 < m; j0 += 8)
        normal_tails(key, base, m - j0 < 8 ? m - j0 : 8, index + j0, tz, z);
}
const bool kHaveAvx2Fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif

}  // namespace

void normal_row(NoiseKey key, std::uint32_t base, int n, float* z, std::int32_t* index) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (kHaveAvx2Fma) return normal_row_avx2(key, base, n, z, index);
#endif
    (void)index;
    for (int i = 0; i < n; ++i)
        z[i] = normal_from_bits<float>(noise_bits(key, base + std::uint32_t(i)));
}

}  // namespace deepsea::camera_rows
