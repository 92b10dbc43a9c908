#pragma once
// The codecs' byte kernels in SSE2 intrinsics (private to deepsea_io): PNG's Paeth filter and
// OpenEXR's ZIP predictor and byte interleave. They stay intrinsics rather than the runtime's
// vocabulary (`#pragma omp simd` loops, GCC vector types over floats): they work on bytes
// widened to 16-bit lanes, shifted across the register or interleaved, and the two serial ones
// carry a dependency from step to step (each pixel's Paeth prediction needs the pixel before
// it, the predictor is a running sum over bytes), so they are vectorised across the bytes of
// one step, where a `omp simd` loop can only run steps side by side. SSE2 is part of x86-64:
// no CPU check; elsewhere the scalar loops beside their callers do all the work.

#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>

namespace deepsea::io_detail {

/// PNG's Paeth filter from a row's second pixel on, one pixel (B <= 8 bytes) per step in 16-bit
/// lanes and without branches: the scalar choice between left, up and up-left mispredicts on
/// real images (12 ns a pixel on the Paeth rows of the authors' frames, 3.8 ns here). Each
/// step loads 8 bytes from the pixel's start, so it stops where that would pass the row's end
/// (the scalar loop does the rest), and stores exactly the pixel's B bytes: in place, the next
/// pixel's filtered bytes lie just after it. The first pixel must be done. Returns the first
/// byte not done.
template <int B>
inline std::size_t paeth_sse2(const std::uint8_t* x, const std::uint8_t* up, std::uint8_t* out,
                              std::size_t n) {
    static_assert(B <= 8);
    const __m128i zero = _mm_setzero_si128(), bytes = _mm_set1_epi16(0xff);
    std::uint8_t pixel[8] = {};
    const auto load = [&](const std::uint8_t* p) {
        return _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)), zero);
    };
    const auto load_pixel = [&](const std::uint8_t* p) {
        std::memcpy(pixel, p, B);
        return load(pixel);
    };
    const auto abs16 = [](__m128i v) {
        return _mm_max_epi16(v, _mm_sub_epi16(_mm_setzero_si128(), v));
    };
    __m128i left = load_pixel(out), upleft = load_pixel(up);
    std::size_t i = B;
    for (; i + 8 <= n; i += B) {
        const __m128i above = load(up + i);
        const __m128i bc = _mm_sub_epi16(above, upleft), ac = _mm_sub_epi16(left, upleft);
        const __m128i pa = abs16(bc), pb = abs16(ac), pc = abs16(_mm_add_epi16(bc, ac));
        // left if pa <= pb and pa <= pc; else up if pb <= pc; else up-left
        const __m128i not_left = _mm_or_si128(_mm_cmpgt_epi16(pa, pb), _mm_cmpgt_epi16(pa, pc));
        const __m128i not_up = _mm_cmpgt_epi16(pb, pc);
        const __m128i other =
            _mm_or_si128(_mm_and_si128(not_up, upleft), _mm_andnot_si128(not_up, above));
        const __m128i pred =
            _mm_or_si128(_mm_and_si128(not_left, other), _mm_andnot_si128(not_left, left));
        left = _mm_and_si128(_mm_add_epi16(load(x + i), pred), bytes);
        upleft = above;
        _mm_storel_epi64(reinterpret_cast<__m128i*>(pixel), _mm_packus_epi16(left, zero));
        std::memcpy(out + i, pixel, B);
    }
    return i;
}

/// OpenEXR's ZIP predictor undone in place from byte 1 on, 16 bytes at a time: each byte
/// becomes the running sum of the bytes up to it, minus 128 per byte after the first.
/// Returns the first byte not done (the caller's scalar loop goes on from in[i - 1]).
inline std::size_t predictor_sums_sse2(unsigned char* in, std::size_t n) {
    std::size_t i = 1;
    const __m128i bias = _mm_set1_epi8(char(-128));
    __m128i carry = _mm_set1_epi8(char(in[0]));
    for (; i + 16 <= n; i += 16) {
        __m128i x = _mm_sub_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in + i)), bias);
        x = _mm_add_epi8(x, _mm_slli_si128(x, 1));
        x = _mm_add_epi8(x, _mm_slli_si128(x, 2));
        x = _mm_add_epi8(x, _mm_slli_si128(x, 4));
        x = _mm_add_epi8(x, _mm_slli_si128(x, 8));
        x = _mm_add_epi8(x, carry);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(in + i), x);
        // byte 15 to every byte: bytes 8..15 doubled into words, word 7 to the high words,
        // then dword 3 to every dword
        carry = _mm_shuffle_epi32(_mm_shufflehi_epi16(_mm_unpackhi_epi8(x, x), 0xff), 0xff);
    }
    return i;
}

/// out[2k] = lo[k], out[2k + 1] = hi[k] for k < half, 16 k at a time. Returns the first k not
/// done.
inline std::size_t interleave_sse2(const unsigned char* lo, const unsigned char* hi,
                                   std::size_t half, unsigned char* out) {
    std::size_t k = 0;
    for (; k + 16 <= half; k += 16) {
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lo + k));
        const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(hi + k));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * k), _mm_unpacklo_epi8(a, b));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * k + 16), _mm_unpackhi_epi8(a, b));
    }
    return k;
}

}  // namespace deepsea::io_detail
#endif  // __SSE2__
