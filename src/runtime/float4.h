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

}  // namespace deepsea
