// The forward scatter's block distances (forward_psf_rows.h, weigh_block_pairs) against the
// pixel-by-pixel weighing: blocks that are not on one surface keep its bits, blocks at one
// distance its sums. And f_row's four pixels at a time against its pixel-by-pixel end; the
// interleaved padded rows and the block pyramid's pair sums against their plain definitions.

#include "forward_psf_rows.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace deepsea::psf_rows {

namespace {

constexpr int kBins = 64;
constexpr float kStep = 0.1f;  // metres between table rows: the table spans 6.4 m

/// Two rows of n pixels: distances, their table positions (as table_rows makes them), radiance.
struct Rows {
    std::vector<float> d[2], frac[2], L[2];
    std::vector<int> idx[2];
};

Rows make_rows(int n, std::mt19937& rng, bool one_distance_a_block) {
    std::uniform_real_distribution<float> dist(0.5f, 6.0f), light(0.0f, 2.0f);
    Rows r;
    for (int row = 0; row < 2; ++row) {
        r.d[row].resize(n);
        r.frac[row].resize(n);
        r.idx[row].resize(n);
        r.L[row].resize(3 * std::size_t(n));
        for (int u = 0; u < n; ++u) {
            float d = dist(rng);
            if (u % 11 == 7) d = 0.0f;  // open water
            if (u % 13 == 5) d = 7.0f;  // beyond the table
            r.d[row][u] = d;
            for (int c = 0; c < 3; ++c) r.L[row][3 * u + c] = light(rng);
        }
    }
    if (one_distance_a_block) {
        for (int u = 0; u < n; ++u)
            r.d[1][u] = r.d[0][u] =
                r.d[0][u / 2 * 2] > 0.0f && r.d[0][u / 2 * 2] < 6.0f ? r.d[0][u / 2 * 2] : 3.0f;
    }
    for (int row = 0; row < 2; ++row) {
        for (int u = 0; u < n; ++u) {
            const float d = r.d[row][u];
            const bool on = d > 0.0f && d < kBins * kStep;
            const float ti = on ? d * (1.0f / kStep) : 0.0f;
            const int i = std::min(int(ti), kBins - 1);
            r.idx[row][u] = on ? i : -1;
            r.frac[row][u] = ti - float(i);
        }
    }
    return r;
}

std::vector<float> table(int stride, std::mt19937& rng) {
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    std::vector<float> t(std::size_t(kBins + 1) * 3 * stride);
    for (float& x : t) x = value(rng);
    return t;
}

/// The two rows' blocks weighed pixel by pixel (weigh_blocks): the exact path.
std::vector<float> pixel_by_pixel(const Rows& r, int n, int stride, const std::vector<float>& tab) {
    const int lanes = 3 * stride, blocks = (n + 1) / 2;
    std::vector<float> exact(std::size_t(blocks) * lanes);
    weigh_blocks(n, 2, stride, r.idx[0].data(), r.frac[0].data(), tab.data(), r.L[0].data(), false,
                 exact.data());
    weigh_blocks(n, 2, stride, r.idx[1].data(), r.frac[1].data(), tab.data(), r.L[1].data(), true,
                 exact.data());
    return exact;
}

/// weigh_block_pairs with block distances at tolerance tol.
std::vector<float> paired(const Rows& r, int n, int stride, const std::vector<float>& tab,
                          float tol) {
    const int lanes = 3 * stride, blocks = (n + 1) / 2;
    std::vector<int> bi(n / 2 + 1);
    std::vector<float> bt(n / 2 + 1), x(std::size_t(blocks) * lanes, -1.0f);
    block_rows(n / 2, r.d[0].data(), r.d[1].data(), 1.0f / kStep, kBins * kStep, kBins, tol,
               bi.data(), bt.data());
    weigh_block_pairs(n, stride, r.idx[0].data(), r.frac[0].data(), r.idx[1].data(),
                      r.frac[1].data(), bi.data(), bt.data(), tab.data(), r.L[0].data(),
                      r.L[1].data(), x.data());
    return x;
}

}  // namespace

TEST(BlockDistances, BlocksApartKeepThePixelByPixelBits) {
    std::mt19937 rng(3);
    for (const int stride : {4, 8}) {
        for (const int n : {36, 37}) {
            const Rows r = make_rows(n, rng, false);
            const std::vector<float> tab = table(stride, rng);
            const std::vector<float> exact = pixel_by_pixel(r, n, stride, tab);
            // a negative tolerance: no block is on one surface
            const std::vector<float> x = paired(r, n, stride, tab, -1.0f);
            for (std::size_t i = 0; i < x.size(); ++i) ASSERT_EQ(x[i], exact[i]) << i;
        }
    }
}

TEST(BlockDistances, ABlockAtOneDistanceIsWeighedThere) {
    std::mt19937 rng(5);
    for (const int stride : {4, 8}) {
        for (const int n : {36, 37}) {
            const Rows r = make_rows(n, rng, true);
            const std::vector<float> tab = table(stride, rng);
            const std::vector<float> exact = pixel_by_pixel(r, n, stride, tab);
            const std::vector<float> x = paired(r, n, stride, tab, 0.02f);
            for (std::size_t i = 0; i < x.size(); ++i)
                ASSERT_NEAR(x[i], exact[i], 1e-5f * std::fabs(exact[i]) + 1e-6f) << i;
        }
    }
}

TEST(FRow, EveryPixelIsItsWeightTimesItsRadianceAndTheGridUpsampled) {
    // f_row runs rows four pixels at a time (two to a vector, their twelve values shuffled into
    // three) and the last n % 4 one by one: each pixel against its definition in double (the
    // rounding of a fused multiply-add, or not, is all that may differ).
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    for (const int n : {36, 37, 38, 39}) {
        const Rows r = make_rows(n, rng, false);
        std::vector<float> sharp(std::size_t(kBins + 1) * 4);
        for (float& x : sharp) x = value(rng);
        const int gw = (n + 1) / 2;
        std::vector<float> coarse(4 * std::size_t(gw + 2), 0.0f);  // padded as f_row reads it
        for (int x = 0; x < gw; ++x)
            for (int c = 0; c < 3; ++c) coarse[4 * (x + 1) + c] = value(rng);
        for (int c = 0; c < 3; ++c) {
            coarse[c] = coarse[4 + c];
            coarse[4 * (gw + 1) + c] = coarse[4 * gw + c];
        }
        std::vector<float> start(3 * std::size_t(n));
        for (float& x : start) x = value(rng);
        for (const bool add : {false, true}) {
            std::vector<float> out = start;
            f_row(n, r.idx[0].data(), r.frac[0].data(), sharp.data(), r.L[0].data(), nullptr,
                  coarse.data(), add, out.data());
            for (int u = 0; u < n; ++u) {
                const int i = r.idx[0][u], odd = u & 1, q = (u >> 1) + odd;
                for (int c = 0; c < 3; ++c) {
                    const double w =
                        i < 0 ? 0.0
                              : sharp[4 * i + c] + double(r.frac[0][u]) *
                                                       (sharp[4 * (i + 1) + c] - sharp[4 * i + c]);
                    const double g0 = coarse[4 * q + c], g1 = coarse[4 * (q + 1) + c];
                    const double want = (add ? double(start[3 * u + c]) : 0.0) +
                                        w * r.L[0][3 * u + c] + g0 +
                                        (odd ? 0.25 : 0.75) * (g1 - g0);
                    ASSERT_NEAR(out[3 * u + c], want, 1e-6 * std::fabs(want))
                        << "pixel " << u << ", channel " << c << (add ? ", added" : "");
                }
            }
        }
    }
}

TEST(PaddedRgbRow, HasTheBitsOfAPaddedRowAPlane) {
    // f_row's grid row: three planes' rows blended and interleaved four cells at a time, the
    // rest one by one, the ends padded or (extend) continued, held >= 0 beyond the grid
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> value(-0.2f, 1.0f);
    for (const int n : {1, 2, 5, 8, 37}) {
        std::vector<float> r0(3 * std::size_t(n)), r1(3 * std::size_t(n));
        for (float& x : r0) x = value(rng);
        for (float& x : r1) x = value(rng);
        const float* a[3] = {r0.data(), r0.data() + n, r0.data() + 2 * n};
        const float* b[3] = {r1.data(), r1.data() + n, r1.data() + 2 * n};
        for (const float w : {0.25f, 0.75f, -0.25f, 1.25f}) {
            for (const bool extend : {false, true}) {
                std::vector<float> want(4 * std::size_t(n + 2), 0.0f), got(want.size(), -1.0f);
                for (int c = 0; c < 3; ++c)
                    padded_row(n, a[c], b[c], w, 4, extend, want.data() + c);
                padded_rgb_row(n, a, b, w, extend, got.data());
                for (std::size_t i = 0; i < want.size(); ++i)
                    ASSERT_EQ(got[i], want[i]) << "n " << n << ", w " << w << ", float " << i;
            }
        }
    }
}

TEST(PairSums, AddEachPairOfBlocksLaneByLane) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    for (const int stride : {4, 8, 12, 16, 20, kMaxStride}) {
        const int lanes = 3 * stride;
        for (const int n : {1, 6, 7}) {
            std::vector<float> src(std::size_t(n) * lanes), start(std::size_t(n + 1) / 2 * lanes);
            for (float& x : src) x = value(rng);
            for (float& x : start) x = value(rng);
            for (const bool add : {false, true}) {
                std::vector<float> dst = start;
                pair_sums(n, stride, src.data(), add, dst.data());
                for (int i = 0; i < (n + 1) / 2; ++i) {
                    for (int k = 0; k < lanes; ++k) {
                        // adding, (d + s0) + s1: the order of the kernel it replaced
                        const float* s = src.data() + std::size_t(2 * i) * lanes + k;
                        const float d = start[std::size_t(i) * lanes + k];
                        const bool pair = 2 * i + 1 < n;
                        const float want = add ? (pair ? (d + s[0]) + s[lanes] : d + s[0])
                                               : (pair ? s[0] + s[lanes] : s[0]);
                        ASSERT_EQ(dst[std::size_t(i) * lanes + k], want) << stride << " " << i;
                    }
                }
            }
        }
    }
}

}  // namespace deepsea::psf_rows
