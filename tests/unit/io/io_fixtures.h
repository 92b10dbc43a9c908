#pragma once
// What the io tests share: files written byte by byte, an image that probes the encoder, the
// message of an error (and the temporary folder fixture).

#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "../temp_folder.h"
#include "deepsea/core/error.h"
#include "deepsea/core/image.h"

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

/// Linear values that probe the encoder: a dense sweep of [0, 1], values a few ulps around
/// every 8-bit code's boundary, and the specials (NaN, inf, negative, -0, above 1).
inline Image probe_image(int w, int h) {
    Image img(w, h, 3);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const std::size_t n = img.data.size();
    for (std::size_t i = 0; i < n; ++i) {
        float v = float(i) / float(n);
        if (i % 3 == 1) v = u(rng) * u(rng) * u(rng);
        if (i % 7 == 2) {
            // near the boundary between codes k and k + 1 (in sRGB), a few ulps either way
            const float s = (float(i % 255) + 0.5f) / 255.0f;
            float lin = s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
            for (int k = int(i % 9) - 4; k != 0; k += k > 0 ? -1 : 1)
                lin = std::nextafter(lin, k > 0 ? 2.0f : -1.0f);
            v = lin;
        }
        img.data[i] = v;
    }
    const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              -0.0f,
                              -1.0f,
                              1.0f,
                              1.5f,
                              1e30f,
                              std::numeric_limits<float>::denorm_min()};
    for (std::size_t i = 0; i < std::size(specials); ++i) img.data[i] = specials[i];
    return img;
}

/// What f throws (a deepsea Error), or "".
inline std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace deepsea::test
