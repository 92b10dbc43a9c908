// The backscatter lookup's last step (backscatter_lookup.h): the grouped form, which lays out a
// span's samples once for eight pixels in one slab, gives the pair-by-pair values bit for bit,
// on rows whose slabs run long, change within eight pixels, and jump at random, with spans of
// every width and alignment and rows cut short at every length.

#include "backscatter_lookup.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

namespace deepsea {
namespace {

TEST(BackscatterLookup, GroupsOfEightArePairByPairBitForBit) {
    const int nk = 12, block = 3 * nk, W = 173;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    // spans of irregular widths (16 is the default lattice's), so groups start anywhere
    std::vector<int> span_end, col0(W), col1(W);
    const int widths[] = {16, 5, 16, 23, 1, 8, 16, 9, 40, 16, 16, 7};
    int u = 0, i = 0;
    for (const int w : widths) {
        for (int x = u; x < std::min(u + w, W); ++x) {
            col0[x] = i * block;
            col1[x] = (i + 1) * block;
        }
        u = std::min(u + w, W);
        span_end.push_back(u);
        ++i;
    }
    ASSERT_EQ(u, W);
    const int ni = i + 1;
    std::vector<float> slice(std::size_t(ni) * block + 1), colw(W), wz(W);
    for (float& x : slice) x = unit(rng);
    for (int x = 0; x < W; ++x) colw[x] = unit(rng);
    const LookupColumns cols{col0.data(), col1.data(), colw.data(), span_end.data(),
                             int(span_end.size())};
    for (int pattern = 0; pattern < 4; ++pattern) {
        std::vector<int> slab(W);
        for (int x = 0; x < W; ++x) {
            wz[x] = unit(rng);
            slab[x] = pattern == 0   ? 3                               // one slab
                      : pattern == 1 ? (x / 19) % (nk - 1)             // long runs
                      : pattern == 2 ? (x / 3) % 2 + 4                 // changes within eight
                                     : int(rng() % unsigned(nk - 1));  // anywhere
        }
        for (int n = 1; n <= W; ++n) {
            std::vector<float> a(3 * std::size_t(n), -1.0f), b(3 * std::size_t(n), -2.0f);
            lookup_row(n, slice.data(), cols, slab.data(), wz.data(), a.data());
            lookup_row_pairs(n, slice.data(), col0.data(), col1.data(), colw.data(), slab.data(),
                             wz.data(), b.data());
            ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0)
                << "pattern " << pattern << ", n " << n;
        }
    }
}

}  // namespace
}  // namespace deepsea
