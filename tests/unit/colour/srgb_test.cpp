// The sRGB curve, its decode tables and the integer encoder (deepsea/colour/srgb.h).

#include "deepsea/colour/srgb.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace deepsea {
namespace {

TEST(Srgb, MatchesIec61966) {
    EXPECT_FLOAT_EQ(srgb_to_linear(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgb_to_linear(1.0f), 1.0f);
    EXPECT_NEAR(srgb_to_linear(0.5f), 0.2140411, 1e-6);
    EXPECT_NEAR(srgb_to_linear(0.04045f), 0.04045 / 12.92, 1e-9);
    EXPECT_NEAR(linear_to_srgb(0.0031308f), 0.0031308 * 12.92, 1e-7);
    EXPECT_NEAR(linear_to_srgb(0.18f), 0.4613561, 1e-6);
    for (int i = 0; i <= 1000; ++i) {
        const float v = float(i) / 1000.0f;
        EXPECT_NEAR(linear_to_srgb(srgb_to_linear(v)), v, 2e-6) << v;
    }
}

TEST(Srgb, DecodesCodesInMemoryAsFilesAre) {
    std::vector<std::uint8_t> c8(256);
    for (int i = 0; i < 256; ++i) c8[i] = std::uint8_t(i);
    std::vector<float> out(256);
    srgb_decode(c8.data(), c8.size(), out.data());
    for (int i = 0; i < 256; ++i) EXPECT_EQ(out[i], srgb_to_linear(float(i) / 255.0f)) << i;
    const std::vector<std::uint16_t> c16{0, 1, 2570, 32768, 65534, 65535};
    out.resize(c16.size());
    srgb_decode(c16.data(), c16.size(), out.data());
    for (std::size_t i = 0; i < c16.size(); ++i) {
        EXPECT_EQ(out[i], srgb_to_linear(float(c16[i]) / 65535.0f)) << c16[i];
    }
}

TEST(SrgbEncode, EveryStrideOfFloatsInZeroToOneGetsTheCodeOfTheFormula) {
    // The table encoder against int(linear_to_srgb(v) * codes + 0.5f), what OpenImageIO
    // stores, over a million float bit patterns spread evenly through [0, 1] (every
    // 1009th), with exposure 1.
    const std::uint32_t one = 0x3f800000u, stride = 1009;
    std::vector<float> linear(one / stride + 1);
    for (std::uint32_t i = 0; i <= one / stride; ++i) {
        const std::uint32_t bits = i * stride;
        std::memcpy(&linear[i], &bits, 4);
    }
    std::vector<std::uint8_t> codes8(linear.size());
    std::vector<std::uint16_t> codes16(linear.size());
    srgb_encode(linear.data(), linear.size(), 1.0, codes8.data());
    srgb_encode(linear.data(), linear.size(), 1.0, codes16.data());
    for (const int bits : {8, 16}) {
        const int codes = bits == 8 ? 255 : 65535;
        for (std::size_t i = 0; i < linear.size(); ++i) {
            const int expect = int(linear_to_srgb(linear[i]) * float(codes) + 0.5f);
            const int got = bits == 8 ? codes8[i] : codes16[i];
            ASSERT_EQ(got, expect) << bits << " bits, value " << linear[i];
        }
    }
}

TEST(SrgbEncode, ValuesOutsideZeroToOneAndAnExposureGetTheCodesOfTheFormula) {
    // Eight values at a time go through the vector path where the CPU has one: every special
    // value in every one of the eight places, and the exposure multiplied in double first.
    // Non-finite values and values <= 0 give 0, values >= 1 the top code.
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> special = {
        0.0f,       -0.0f, -1e-30f,     -0.5f,      1.0f,
        1.0000001f, 3e38f, inf,         -inf,       std::numeric_limits<float>::quiet_NaN(),
        1e-38f,     0.5f,  0.99999994f, 0.0031308f, 1e-45f,
        2.0f};
    std::vector<float> linear(special.size() * 9);
    for (std::size_t i = 0; i < linear.size(); ++i) {
        linear[i] = i % 9 == 0 ? special[(i / 9) % special.size()] : 0.25f + 1e-3f * i;
    }
    for (const double exposure : {1.0, 0.7, 3.3}) {
        std::vector<std::uint8_t> codes(linear.size());
        srgb_encode(linear.data(), linear.size(), exposure, codes.data());
        for (std::size_t i = 0; i < linear.size(); ++i) {
            const float v = float(linear[i] * exposure);
            const int expect = !std::isfinite(v) || v <= 0.0f ? 0
                               : v >= 1.0f                    ? 255
                                           : int(linear_to_srgb(v) * 255.0f + 0.5f);
            ASSERT_EQ(int(codes[i]), expect) << "value " << linear[i] << " times " << exposure;
        }
    }
}

TEST(SrgbEncode, FloatsAroundEveryEightBitBoundaryGetTheCodeOfTheFormula) {
    // The vector path reads each value's bucket entry (its start code and where its one
    // threshold lies): every float within 300 ulps of each code's first float, where the
    // entry's comparison decides, and the buckets' own first floats. A mistake in the
    // entry's threshold bits or in its comparison moves a code at these values.
    const auto code = [](float v) { return int(linear_to_srgb(v) * 255.0f + 0.5f); };
    std::vector<float> linear;
    for (int k = 1; k <= 255; ++k) {
        std::uint32_t lo = 0, hi = 0x3f800000u;  // code(lo) < k <= code(hi)
        while (hi - lo > 1) {
            const std::uint32_t mid = lo + (hi - lo) / 2;
            float f;
            std::memcpy(&f, &mid, 4);
            (code(f) >= k ? hi : lo) = mid;
        }
        for (std::uint32_t b = hi - 300; b <= hi + 300 && b < 0x3f800000u; ++b) {
            float f;
            std::memcpy(&f, &b, 4);
            linear.push_back(f);
        }
    }
    for (std::uint32_t b = 0x38000000u; b < 0x3f800000u; b += 1u << 15) {
        float f;
        std::memcpy(&f, &b, 4);
        linear.push_back(f);
    }
    std::vector<std::uint8_t> codes(linear.size());
    srgb_encode(linear.data(), linear.size(), 1.0, codes.data());
    for (std::size_t i = 0; i < linear.size(); ++i)
        ASSERT_EQ(int(codes[i]), code(linear[i])) << "value " << linear[i];
}

TEST(SrgbEncode, FloatsAroundEveryBoundaryOfAnExposedCodeGetTheCodeOfTheFormula) {
    // With an exposure, the vector path tables the codes on the input's own bits (the 255
    // inputs where float(v * exposure)'s code steps up, found here again by bisection with the
    // formula): every float within 300 ulps of each, of the first input whose product is
    // infinite, and a spread of the rest, at exposures from tiny to huge.
    const auto code = [](float v, double exposure) {
        const float x = float(v * exposure);
        return !std::isfinite(x) || x <= 0.0f ? 0
               : x >= 1.0f                    ? 255
                                              : int(linear_to_srgb(x) * 255.0f + 0.5f);
    };
    const auto from = [](std::uint32_t b) {
        float f;
        std::memcpy(&f, &b, 4);
        return f;
    };
    for (const double exposure : {1.0, 0.37, 17.25, 3100.0, 1e-3, 2.5e30, 1e-30, 0.999}) {
        std::vector<std::uint32_t> edges;
        for (int k = 1; k <= 256; ++k) {  // 256: the first input whose product is infinite
            std::uint32_t lo = 0, hi = 0x7f800000u;
            while (hi - lo > 1) {
                const std::uint32_t mid = lo + (hi - lo) / 2;
                const bool past = k == 256 ? std::isinf(float(from(mid) * exposure))
                                           : code(from(mid), exposure) >= k;
                (past ? hi : lo) = mid;
            }
            edges.push_back(hi);
        }
        std::vector<float> linear;
        for (const std::uint32_t e : edges)
            for (std::uint32_t b = e > 300 ? e - 300 : 0; b <= e + 300 && b < 0x7f800000u; ++b)
                linear.push_back(from(b));
        for (std::uint32_t b = 0; b < 0x7f800000u; b += 0x7f800000u / 4099)
            linear.push_back(from(b));
        for (std::uint32_t b = 0x80000000u; b < 0xff800000u; b += 0x7f800000u / 97)
            linear.push_back(from(b));
        for (const std::uint32_t b : {0x7f800000u, 0xff800000u, 0x7fc00000u, 0x80000000u})
            linear.push_back(from(b));
        while (linear.size() % 8) linear.push_back(0.5f);
        std::vector<std::uint8_t> codes(linear.size());
        srgb_encode(linear.data(), linear.size(), exposure, codes.data());
        for (std::size_t i = 0; i < linear.size(); ++i)
            ASSERT_EQ(int(codes[i]), code(linear[i], exposure))
                << "value " << linear[i] << " times " << exposure;
    }
}

TEST(SrgbEncode, EveryFloatAtTheGivenExposuresGetsTheCodeOfTheScalarPath) {
    // All 2^32 float bit patterns through the vector path (whole buffers) against the scalar
    // path (srgb_encode of one value, which the vector path leaves to it), at the exposures in
    // DEEPSEA_SRGB_EXPOSURES (comma-separated; about a minute each on one core).
    const char* list = std::getenv("DEEPSEA_SRGB_EXPOSURES");
    if (!list) GTEST_SKIP() << "set DEEPSEA_SRGB_EXPOSURES, e.g. 1,0.37,3100,2.5e30,1e-30";
    std::vector<double> exposures;
    for (const char* p = list; *p;) {
        char* end = nullptr;
        exposures.push_back(std::strtod(p, &end));
        ASSERT_NE(end, p) << list;
        p = *end == ',' ? end + 1 : end;
    }
    std::vector<float> linear(1 << 20);
    std::vector<std::uint8_t> codes(linear.size());
    for (const double exposure : exposures) {
        for (std::uint64_t first = 0; first < (std::uint64_t(1) << 32); first += linear.size()) {
            for (std::size_t i = 0; i < linear.size(); ++i) {
                const std::uint32_t b = std::uint32_t(first + i);
                std::memcpy(&linear[i], &b, 4);
            }
            srgb_encode(linear.data(), linear.size(), exposure, codes.data());
            for (std::size_t i = 0; i < linear.size(); ++i) {
                std::uint8_t one = 0;
                srgb_encode(&linear[i], 1, exposure, &one);
                ASSERT_EQ(codes[i], one) << "bits " << first + i << " times " << exposure;
            }
        }
    }
}

}  // namespace
}  // namespace deepsea
