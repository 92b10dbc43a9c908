#pragma once
// Internal: four floats as one vector (GCC and Clang vector extensions: SSE or NEON
// registers, or plain floats where neither exists), loaded and stored unaligned. The runtime's
// kernels that handle a pixel's three channels at once (interleaved RGB) use it.

#include <cstring>

namespace deepsea {

typedef float Float4 __attribute__((vector_size(16)));

inline Float4 load4(const float* p) {
    Float4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store4(float* p, Float4 v) { std::memcpy(p, &v, sizeof v); }
inline Float4 splat(float w) { return Float4{w, w, w, w}; }
/// Lane by lane std::min(a, b) and std::max(a, b).
inline Float4 min4(Float4 a, Float4 b) { return b < a ? b : a; }
inline Float4 max4(Float4 a, Float4 b) { return a < b ? b : a; }

/// Eight floats as one vector (an AVX register, or two SSE ones): a pixel's 8 interleaved
/// values at once. (Only inside functions, which inline these: no call passes one, so GCC's
/// note that AVX changes the ABI of such calls does not apply.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
typedef float Float8 __attribute__((vector_size(32)));

inline Float8 load8(const float* p) {
    Float8 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
/// Lane k of v in all eight lanes (a broadcast: GCC builds a braced list of eight floats from
/// inserts).
template <int k>
inline Float8 splat8(Float4 v) {
    return __builtin_shufflevector(v, v, k, k, k, k, k, k, k, k);
}
#pragma GCC diagnostic pop

}  // namespace deepsea
