// The PNG writer's literal-and-run zlib streams (src/io/deflate_runs.h), inflated by two
// decoders (libdeflate, ISA-L) on inputs that reach each of its paths: noise (stored blocks),
// skewed bytes (Huffman codes at the length limit), runs across blocks, tiny inputs.

#include "deflate_runs.h"

#include <gtest/gtest.h>
#include <isa-l.h>
#include <libdeflate.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace deepsea {
namespace {

using io_detail::deflate_runs;
using io_detail::deflate_runs_bound;

std::vector<std::uint8_t> compress(const std::vector<std::uint8_t>& in) {
    std::vector<std::uint8_t> out(deflate_runs_bound(in.size()));
    out.resize(deflate_runs(in.data(), in.size(), out.data()));
    EXPECT_LE(out.size() + 8, deflate_runs_bound(in.size()));
    return out;
}

/// Inflates `z` with libdeflate and with ISA-L and expects `in` back from both.
void expect_round_trip(const std::vector<std::uint8_t>& in, const std::string& what) {
    const std::vector<std::uint8_t> z = compress(in);
    std::vector<std::uint8_t> back(in.size() + 1);
    libdeflate_decompressor* d = libdeflate_alloc_decompressor();
    std::size_t got = 0;
    EXPECT_EQ(libdeflate_zlib_decompress(d, z.data(), z.size(), back.data(), back.size(), &got),
              LIBDEFLATE_SUCCESS)
        << what;
    libdeflate_free_decompressor(d);
    back.resize(got);
    EXPECT_TRUE(back == in) << what << ": libdeflate";

    std::vector<std::uint8_t> back2(in.size() + 1);
    inflate_state s;
    isal_inflate_init(&s);
    s.crc_flag = ISAL_ZLIB;
    s.next_in = const_cast<std::uint8_t*>(z.data());
    s.avail_in = std::uint32_t(z.size());
    s.next_out = back2.data();
    s.avail_out = std::uint32_t(back2.size());
    EXPECT_EQ(isal_inflate_stateless(&s), ISAL_DECOMP_OK) << what;
    back2.resize(s.total_out);
    EXPECT_TRUE(back2 == in) << what << ": ISA-L";
}

TEST(DeflateRuns, InflatesBackOnEveryKindOfInput) {
    std::mt19937 rng(7);
    expect_round_trip({42}, "one byte");
    expect_round_trip({1, 1, 1, 1, 1, 1}, "a run from the second byte");
    std::vector<std::uint8_t> noise(200000);
    for (auto& b : noise) b = std::uint8_t(rng());
    expect_round_trip(noise, "uniform noise");  // stored blocks
    std::vector<std::uint8_t> zeros(300001, 0);
    expect_round_trip(zeros, "zeros");  // runs of 258 across blocks
    std::normal_distribution<float> residual(0.0f, 3.0f);
    std::vector<std::uint8_t> rows(150000);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        // Filtered-row-like residuals with flat stretches: literals and runs of every length.
        // A negative residual wraps modulo 256, as a filtered byte does (through int: a float
        // out of the byte's range has no defined conversion).
        const int r = int(std::lround(residual(rng)));
        rows[i] = (i / 1000) % 3 == 0 ? std::uint8_t(i / 3000) : std::uint8_t(r);
    }
    expect_round_trip(rows, "residuals and runs");
    // Byte b about 1.6^-b as often: Huffman's lengths pass the 12-bit limit and are folded.
    std::vector<std::uint8_t> skewed;
    for (int b = 0; b < 40; ++b) {
        const int n = int(200000.0 / std::pow(1.6, b)) + 1;
        for (int k = 0; k < n; ++k) skewed.push_back(std::uint8_t(b));
    }
    std::shuffle(skewed.begin(), skewed.end(), rng);
    expect_round_trip(skewed, "skewed bytes");
}

TEST(DeflateRuns, CodesRunsAndSkewedBytesSmall) {
    EXPECT_LT(compress(std::vector<std::uint8_t>(100000, 9)).size(), 1000u);
    std::mt19937 rng(3);
    std::vector<std::uint8_t> two(100000);
    for (auto& b : two) b = std::uint8_t(rng() & 1);  // a bit a byte, as literals and runs
    EXPECT_LT(compress(two).size(), 100000u / 4);
}

}  // namespace
}  // namespace deepsea
