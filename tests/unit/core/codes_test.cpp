// core's quantise8 (the 8-bit writers' and the camera stage's codes): its vector steps give the
// scalar formula's bits for every kind of value, including the halfway points, NaN and values
// out of [0, 1].
#include "deepsea/core/codes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "deepsea/core/random.h"

namespace deepsea {
namespace {

std::uint8_t scalar_code(float v) {
    const float x = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
    return std::uint8_t(x * 255.0f + 0.5f);
}

TEST(Quantise8, VectorStepsGiveTheScalarFormulasCodes) {
    std::vector<float> v;
    for (int k = 0; k <= 255; ++k) {  // each code's halfway points and their neighbours
        const float mid = (k + 0.5f) / 255.0f;
        v.push_back(mid);
        v.push_back(std::nextafter(mid, 0.0f));
        v.push_back(std::nextafter(mid, 2.0f));
        v.push_back(k / 255.0f);
    }
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (float x : {nan, -nan, inf, -inf, -0.0f, 0.0f, 1.0f, 1.5f, -1e-30f, 1e30f, 1e-45f})
        v.push_back(x);
    Rng rng(7);
    for (int i = 0; i < 20000; ++i) v.push_back(float(rng.uniform() * 1.2 - 0.1));
    for (std::size_t offset : {0, 1, 5}) {  // unaligned starts, and a scalar tail
        std::vector<std::uint8_t> codes(v.size() - offset);
        quantise8(v.data() + offset, codes.size(), codes.data());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < codes.size(); ++i)
            wrong += codes[i] != scalar_code(v[offset + i]);
        EXPECT_EQ(wrong, 0u) << offset;
    }
    std::uint8_t c[16];
    const std::vector<float> edge(16, nan);
    quantise8(edge.data(), 16, c);
    EXPECT_EQ(c[0], 0);
}

}  // namespace
}  // namespace deepsea
