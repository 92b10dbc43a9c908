// The sensor kernel's rows (rows.h's sensor_row; with AVX2 and FMA, sensor_avx2.cpp): a value's
// DN does not depend on where the radiance lies in memory or on how long the chunk is; the image
// the kernel makes in its loop is the frame's table read at the DN it returns (the exact path's
// values too), and the same without the raw DN kept; the Gaussian path's DN are those of the
// noise model in double; brightest_row gives each pixel its histogram bin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "deepsea/camera/noise.h"
#include "rows.h"

namespace deepsea {
namespace {

using camera_rows::AlignedBytes;
using camera_rows::kChunk;

/// One chunk's aligned scratch and inputs (kChunk + 16 values each, so that the radiance can be
/// shifted by a float).
struct Chunk {
    static constexpr std::size_t kFloats = kChunk + 16;
    AlignedBytes bytes{17 * kFloats * 4};
    float* at(int k) const { return bytes.at<float>(std::size_t(k) * kFloats * 4); }
    std::int32_t* ints(int k) const { return bytes.at<std::int32_t>(std::size_t(k) * kFloats * 4); }
    float *radiance = at(0), *response = at(1), *dsnu = at(2), *shown = at(3);
    std::uint8_t* codes = reinterpret_cast<std::uint8_t*>(at(4));

    camera_rows::RowBuffers rows(const float* rad) const {
        return {rad,   response, dsnu,     nullptr, at(5),  at(6),  ints(7),
                at(8), at(9),    ints(10), at(11),  at(12), at(13), at(14)};
    }
    const float* raw() const { return at(8); }
};

/// A sensor whose chunk spans dark values, ordinary ones and the full well (the exact path at
/// both ends: read noise below kGaussianReadNoiseFrom).
camera_rows::SensorParams sensor(float read_noise) {
    camera_rows::SensorParams p;
    p.exposure_time_ms = 2.0f;
    p.dark_electrons = 0.3f;
    p.full_well = 9000.0f;
    p.gain = 0.4f;
    p.black = 16.0f;
    p.max_dn = 4095.0f;
    p.read_noise = read_noise;
    p.poisson_below = float(poisson_below(read_noise));
    p.shot_key = noise_key(11);
    p.read_key = noise_key(12);
    return p;
}

void fill(const Chunk& c) {
    for (int i = 0; i < int(Chunk::kFloats); ++i) {
        const double x = double(i) / 225.0;  // the full well within 225 values
        c.radiance[i] = float(x < 0.2 ? 0.02 * x : 5.5 * x * x);
        c.response[i] = float(1000.0 * (1.0 + 0.01 * std::sin(0.7 * i)));
        c.dsnu[i] = float(0.8 * std::cos(1.3 * i));
    }
}

TEST(SensorRows, DnDoNotDependOnTheRadiancesAlignmentOrTheChunksLength) {
    if (!camera_rows::kSensorAvx2) GTEST_SKIP() << "the generic rows read aligned radiance only";
    for (const float read_noise : {1.5f, 2.5f}) {
        const camera_rows::SensorParams p = sensor(read_noise);
        Chunk a, b;
        fill(a);
        fill(b);
        // b's radiance one float further on: unaligned, the same values.
        std::memmove(b.radiance + 1, b.radiance, kChunk * sizeof(float));
        camera_rows::sensor_row(p, 3000, kChunk, a.rows(a.radiance));
        camera_rows::sensor_row(p, 3000, kChunk, b.rows(b.radiance + 1));
        EXPECT_EQ(std::memcmp(a.raw(), b.raw(), kChunk * sizeof(float)), 0) << read_noise;
        // Shorter chunks (vector tails of 1 to 7 values) give their values' same bits.
        for (const int n : {1, 7, 9, 225, 383}) {
            Chunk s;
            fill(s);
            camera_rows::sensor_row(p, 3000, n, s.rows(s.radiance));
            EXPECT_EQ(std::memcmp(a.raw(), s.raw(), std::size_t(n) * sizeof(float)), 0)
                << read_noise << " " << n;
        }
    }
}

TEST(SensorRows, ImageMadeInTheLoopIsTheTableAtTheReturnedDn) {
    if (!camera_rows::kSensorAvx2) GTEST_SKIP() << "the image is made in the loop with AVX2 only";
    std::vector<float> lut(3 * 4096);
    std::vector<std::uint8_t> code_lut(lut.size());
    for (std::size_t k = 0; k < lut.size(); ++k) {
        lut[k] = float(std::sqrt(double(k / 3) / 4095.0) * (1.0 - 0.1 * double(k % 3)));
        code_lut[k] = std::uint8_t(k * 7 % 256);
    }
    for (const float read_noise : {1.5f, 2.5f}) {
        const camera_rows::SensorParams p = sensor(read_noise);
        for (const int n : {kChunk, 225}) {
            Chunk c;
            fill(c);
            camera_rows::RowBuffers b = c.rows(c.radiance + 1);  // unaligned
            b.lut = lut.data();
            b.shown = c.shown;
            camera_rows::sensor_row(p, 77, n, b);
            Chunk d;
            fill(d);
            camera_rows::RowBuffers e = d.rows(d.radiance + 1);
            e.code_lut = code_lut.data();
            e.codes = d.codes;
            camera_rows::sensor_row(p, 77, n, e);
            int clipped = 0, dark = 0;
            for (int i = 0; i < n; ++i) {
                const int at = 3 * int(c.raw()[i]) + i % 3;
                ASSERT_EQ(c.shown[i], lut[at]) << read_noise << " " << n << " " << i;
                ASSERT_EQ(int(d.codes[i]), int(code_lut[at])) << read_noise << " " << n << " " << i;
                ASSERT_EQ(c.raw()[i], d.raw()[i]);
                clipped += c.raw()[i] >= p.gain * p.full_well;
                dark += c.raw()[i] < p.black + 3.0f;
            }
            EXPECT_GT(clipped, 0);  // values near the full well (the exact path) were checked
            EXPECT_GT(dark, 0);
        }
    }
}

TEST(SensorRows, WithoutRawDnTheImageIsTheSame) {
    // SensorParams::keep_raw false (the image made in the loop, no raw layer or meter): the
    // same display values and codes; the raw DN written are the exact path's alone, the same.
    if (!camera_rows::kSensorAvx2) GTEST_SKIP() << "the image is made in the loop with AVX2 only";
    std::vector<float> lut(3 * 4096);
    std::vector<std::uint8_t> code_lut(lut.size());
    for (std::size_t k = 0; k < lut.size(); ++k) {
        lut[k] = float(double(k) / double(lut.size()));
        code_lut[k] = std::uint8_t(k * 5 % 256);
    }
    for (const float read_noise : {1.5f, 2.5f}) {  // with and without the Poisson path
        for (const int n : {kChunk, 225}) {
            for (const bool codes : {false, true}) {
                camera_rows::SensorParams p = sensor(read_noise);
                Chunk all, part;
                for (const Chunk* c : {&all, &part}) {
                    fill(*c);
                    std::fill(c->at(8), c->at(8) + kChunk, -1.0f);  // raw: not written
                    camera_rows::RowBuffers b = c->rows(c->radiance + 1);
                    if (codes) {
                        b.code_lut = code_lut.data();
                        b.codes = c->codes;
                    } else {
                        b.lut = lut.data();
                        b.shown = c->shown;
                    }
                    p.keep_raw = c == &all;
                    camera_rows::sensor_row(p, 901, n, b);
                }
                const std::size_t bytes = std::size_t(n) * (codes ? 1 : sizeof(float));
                EXPECT_EQ(
                    std::memcmp(codes ? static_cast<const void*>(all.codes) : all.shown,
                                codes ? static_cast<const void*>(part.codes) : part.shown, bytes),
                    0)
                    << read_noise << " " << n << " " << codes;
                int written = 0;
                for (int i = 0; i < n; ++i) {
                    if (part.raw()[i] < 0.0f) continue;
                    ASSERT_EQ(part.raw()[i], all.raw()[i]) << read_noise << " " << n << " " << i;
                    ++written;
                }
                EXPECT_GT(written, 0);  // the exact path's values (near the full well)
                EXPECT_LT(written, n);  // and not the others
            }
        }
    }
}

TEST(SensorRows, GaussianPathIsTheNoiseModelInDouble) {
    const camera_rows::SensorParams p = sensor(2.5f);  // Gaussian path below the full well
    Chunk c;
    fill(c);
    const int shift = camera_rows::kSensorAvx2 ? 1 : 0;  // unaligned where the kernel reads so
    camera_rows::sensor_row(p, 5000, kChunk, c.rows(c.radiance + shift));
    int checked = 0, equal = 0;
    for (int i = 0; i < kChunk; ++i) {
        const double mean =
            std::max(0.0, double(c.radiance[i + shift])) * c.response[i] * p.exposure_time_ms +
            p.dark_electrons;
        const double variance = mean + double(p.read_noise) * p.read_noise;
        const double sigma = std::sqrt(variance);
        if (mean + 5.5 * sigma >= p.full_well) continue;  // the exact path's
        const double z = normal_from_bits<double>(noise_bits(p.shot_key, 5000u + i));
        const double e = mean + sigma * z + mean / (6.0 * variance) * (z * z - 1.0) + c.dsnu[i];
        const double dn = std::min(std::max(std::floor(p.gain * e + p.black + 0.5), 0.0), 4095.0);
        ASSERT_LE(std::fabs(c.raw()[i] - dn), 1.0) << i;  // float rounding at a half DN
        ++checked;
        equal += c.raw()[i] == dn;
    }
    EXPECT_GT(checked, kChunk / 2);
    EXPECT_GE(equal, checked - 2);
}

}  // namespace
}  // namespace deepsea

namespace deepsea {
namespace {

TEST(SensorRows, BrightestRowGivesEachPixelsBinInOrder) {
    // Whole DN in every channel order, past `last` too; every length from 1 to 40 pixels (the
    // AVX2 loop's groups of 8 and its generic end).
    const std::int32_t last = 900;
    std::vector<float> raw(3 * 40);
    for (std::size_t i = 0; i < raw.size(); ++i) raw[i] = float((i * 7919 + 13) % 1000);
    for (int pixels = 1; pixels <= 40; ++pixels) {
        std::vector<std::int32_t> bins(std::size_t(pixels), -1);
        camera_rows::brightest_row(pixels, raw.data(), last, bins.data());
        for (int p = 0; p < pixels; ++p) {
            const float b = std::max(raw[3 * p], std::max(raw[3 * p + 1], raw[3 * p + 2]));
            const std::int32_t bin = std::min(std::int32_t(b), last);
            ASSERT_EQ(bins[std::size_t(p)], bin) << pixels << " " << p;
        }
    }
}

}  // namespace
}  // namespace deepsea
