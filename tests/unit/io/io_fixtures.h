#pragma once
// What the io tests share: files written byte by byte (and the temporary folder fixture).

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "../temp_folder.h"

namespace deepsea::test {

inline void write_bytes(const std::string& p, const std::string& bytes) {
    std::ofstream os(p, std::ios::binary);
    os.write(bytes.data(), std::streamsize(bytes.size()));
}

template <typename T>
std::string raw(const std::vector<T>& v) {
    // The test machine is little-endian (x86-64/aarch64), as are .npy '<' and PFM scale < 0.
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

inline std::string be32(std::uint32_t v) {
    return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

}  // namespace deepsea::test
