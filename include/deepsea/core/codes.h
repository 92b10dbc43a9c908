#pragma once
/// \file Display values to 8-bit codes: the one quantiser of PNG and JPEG writers (io's
/// encode_display) and of the camera stage's codes (CameraLayerSet::codes8), so that both make
/// the same bits.

#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace deepsea {

/// codes[i] = trunc(min(max(v[i], 0), 1) x 255 + 0.5), NaN to 0: a product and a sum, each
/// rounded (never fused). 16 values a step in SSE2 (part of x86-64): GCC does not vectorise
/// the float-to-byte conversion, and the scalar loop took about 4 ms of CPU per 800x800 frame.
inline void quantise8(const float* v, std::size_t n, std::uint8_t* codes) {
    std::size_t i = 0;
#if defined(__SSE2__)
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), scale = _mm_set1_ps(255.0f),
                 half = _mm_set1_ps(0.5f);
    const auto four = [&](const float* p) {
        // maxps gives its second operand (0) where the value is NaN, as the scalar loop does.
        const __m128 x = _mm_min_ps(_mm_max_ps(_mm_loadu_ps(p), zero), one);
        return _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(x, scale), half));
    };
    for (; i + 16 <= n; i += 16) {
        const __m128i a = _mm_packs_epi32(four(v + i), four(v + i + 4));
        const __m128i b = _mm_packs_epi32(four(v + i + 8), four(v + i + 12));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(codes + i), _mm_packus_epi16(a, b));
    }
#endif
    for (; i < n; ++i) {
        const float x = v[i] > 0.0f ? (v[i] < 1.0f ? v[i] : 1.0f) : 0.0f;
        codes[i] = std::uint8_t(x * 255.0f + 0.5f);
    }
}

}  // namespace deepsea
