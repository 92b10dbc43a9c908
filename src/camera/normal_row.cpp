// Rows of standard normal deviates (noise.h's normal_from_bits): the one generator of the
// camera's fixed patterns and temporal noise. With AVX2 and FMA, 8 values at a time: the hash,
// t's octave and mantissa from its float bits, and the octave table's five coefficients read
// with vpermps (one instruction each: the table has 8 octaves); the 0.39 % of values below the
// table (Giles' erfinv) gathered and computed 8 at a time afterwards.

#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "rows.h"

namespace deepsea::camera_rows {

namespace {

/// The values below the table (gathered: `index`, m of them), computed in a vector loop, then
/// scattered. `tz`: scratch for m floats.
[[gnu::always_inline]] inline void tails(NoiseKey key, std::uint32_t base, int m,
                                         const std::int32_t* index, float* tz, float* z) {
#pragma omp simd
    for (int j = 0; j < m; ++j)
        tz[j] = normal_tail_from_bits<float>(noise_bits(key, base + std::uint32_t(index[j])));
    for (int j = 0; j < m; ++j) z[index[j]] = tz[j];
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,fma"))) void normal_row_avx2(NoiseKey key, std::uint32_t base, int n,
                                                         float* z, std::int32_t* index) {
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i mul = _mm256_set1_epi32(std::int32_t(key.mul));
    const __m256i add = _mm256_set1_epi32(std::int32_t(key.add));
    const __m256i h1 = _mm256_set1_epi32(std::int32_t(0xed5ad4bbu));
    const __m256i h2 = _mm256_set1_epi32(std::int32_t(0xac4c1b51u));
    const __m256i h3 = _mm256_set1_epi32(std::int32_t(0x31848babu));
    const __m256i low23 = _mm256_set1_epi32(0x7fffff), one = _mm256_set1_epi32(0x3f800000);
    const __m256i sign = _mm256_set1_epi32(std::int32_t(0x80000000u));
    const __m256i lsb = _mm256_set1_epi32(1), low24 = _mm256_set1_epi32(0xffffff);
    const __m256i bias = _mm256_set1_epi32(125 + 25),
                  below = _mm256_set1_epi32(126 + 25 - kNormalOctaves);
    const __m256 mid = _mm256_set1_ps(1.5f);
    __m256 c[5];
    for (int k = 0; k < 5; ++k) c[k] = _mm256_loadu_ps(kNormalTable[k]);
    // The scrambled counters counter * mul + add (mod 2^32) of 8 values, stepped by 8 mul: one
    // add per 8 values instead of a broadcast, a multiply and an add.
    __m256i scrambled = _mm256_add_epi32(
        _mm256_mullo_epi32(_mm256_add_epi32(_mm256_set1_epi32(std::int32_t(base)), lanes), mul),
        add);
    const __m256i stride = _mm256_set1_epi32(std::int32_t(8u * key.mul));
    int m = 0, i = 0;
    for (; i + 8 <= n; i += 8) {
        __m256i x = scrambled;  // triple32
        scrambled = _mm256_add_epi32(scrambled, stride);
        x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 17));
        x = _mm256_mullo_epi32(x, h1);
        x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 11));
        x = _mm256_mullo_epi32(x, h2);
        x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
        x = _mm256_mullo_epi32(x, h3);
        x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 14));
        // t = (2 i + 1) / 2^25, i = bits 8-30: the float of 2 i + 1 (exact, below 2^24) has
        // t's mantissa, and its exponent is t's + 25.
        const __m256i odd = _mm256_and_si256(_mm256_or_si256(_mm256_srli_epi32(x, 7), lsb), low24);
        const __m256i tb = _mm256_castps_si256(_mm256_cvtepi32_ps(odd));
        const __m256i e = _mm256_srli_epi32(tb, 23);
        const __m256i octave = _mm256_sub_epi32(bias, e);
        const __m256 y = _mm256_sub_ps(
            _mm256_castsi256_ps(_mm256_or_si256(_mm256_and_si256(tb, low23), one)), mid);
        __m256 p = _mm256_permutevar8x32_ps(c[4], octave);
        for (int k = 3; k >= 0; --k)
            p = _mm256_fmadd_ps(p, y, _mm256_permutevar8x32_ps(c[k], octave));
        p = _mm256_xor_ps(p, _mm256_castsi256_ps(_mm256_and_si256(x, sign)));
        _mm256_storeu_ps(z + i, p);
        int tail = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(below, e)));
        while (tail) {  // rare: 3 % of groups of 8
            index[m++] = i + __builtin_ctz(unsigned(tail));
            tail &= tail - 1;
        }
    }
    for (; i < n; ++i) z[i] = normal_from_bits<float>(noise_bits(key, base + std::uint32_t(i)));
    float tz[8];
    for (int j0 = 0; j0 < m; j0 += 8) tails(key, base, m - j0 < 8 ? m - j0 : 8, index + j0, tz, z);
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
