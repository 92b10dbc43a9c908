#pragma once
/// \file FNV-1a (64 bit): the one hash deepsea keys things by (an asset's inputs, its stored
/// floats, long temporary names, a frame's noise). Not cryptographic; stable across machines.

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace deepsea {

inline constexpr std::uint64_t kFnv1aBasis = 1469598103934665603ull;

/// FNV-1a of `n` bytes, continuing from `h` (the basis for a fresh hash).
inline std::uint64_t fnv1a64(const void* bytes, std::size_t n, std::uint64_t h = kFnv1aBasis) {
    const auto* p = static_cast<const unsigned char*>(bytes);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

inline std::uint64_t fnv1a64(std::string_view text, std::uint64_t h = kFnv1aBasis) {
    return fnv1a64(text.data(), text.size(), h);
}

}  // namespace deepsea
