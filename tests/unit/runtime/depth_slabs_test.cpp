// The backscatter lookup's depth slabs (depth_slabs.h): the grouped form, which reads a slab's
// values once for eight pixels whose buckets all fall in it, gives the pixel-by-pixel values
// bit for bit, on depths that sit on and beside every sample and every bucket edge, in runs
// and scattered, at every alignment; and the slab found holds its depth.

#include "depth_slabs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace deepsea {
namespace {

/// Samples 0 = z_0 < ... < z_K = z_max: uniform, or growing as exp (the default lattice's
/// kind, thin slabs near the camera).
std::vector<double> samples(int K, double z_max, bool log) {
    std::vector<double> z(K + 1);
    for (int k = 0; k <= K; ++k) {
        const double t = double(k) / K;
        z[k] = log ? z_max * (std::exp(3.0 * t) - 1.0) / (std::exp(3.0) - 1.0) : z_max * t;
    }
    return z;
}

/// Depths on and one float either side of every sample and bucket edge, open water (0),
/// beyond z_max, and smooth and random runs.
std::vector<float> hard_depths(const DepthSlabs& s) {
    std::vector<float> d;
    auto near = [&](float x) {
        for (const float y : {std::nextafter(x, 0.0f), x, std::nextafter(x, 1e30f)})
            if (y >= 0.0f) d.push_back(y);
    };
    for (const float x : s.z) near(x);
    for (std::size_t b = 0; b < s.bucket.size(); ++b) near(float(b) / s.bucket_scale);
    const std::size_t edges = d.size();
    std::sort(d.begin(), d.end());  // runs: groups mostly within one slab
    for (std::size_t i = 0; i < edges; ++i) d.push_back(d[i]);
    std::mt19937 rng(7);
    std::shuffle(d.begin() + edges, d.end(), rng);  // and the same depths scattered
    std::uniform_real_distribution<float> any(0.0f, 1.2f * s.z.back());
    for (int i = 0; i < 20000; ++i) d.push_back(i % 97 == 0 ? 0.0f : any(rng));
    for (int i = 0; i < 20000; ++i) d.push_back(2.0f + 3.0f * std::sin(i * 1e-3f));
    d.push_back(1e6f);
    return d;
}

TEST(DepthSlabs, EightAtATimeIsPixelByPixelBitForBit) {
    for (const bool log : {false, true}) {
        for (const int K : {1, 16, 64, 200}) {
            const DepthSlabs s(samples(K, 27.172, log));
            const std::vector<float> d = hard_depths(s);
            for (int offset = 0; offset < 8; ++offset) {
                const int n = int(d.size()) - offset;
                std::vector<int> k1(n), k2(n);
                std::vector<float> w1(n), w2(n);
                depth_cells_each(n, d.data() + offset, s, k1.data(), w1.data());
                depth_cells(n, d.data() + offset, s, k2.data(), w2.data());
                ASSERT_EQ(k1, k2) << "K " << K << (log ? " log" : " uniform");
                ASSERT_EQ(0, std::memcmp(w1.data(), w2.data(), n * sizeof(float)))
                    << "K " << K << (log ? " log" : " uniform");
            }
        }
    }
}

TEST(DepthSlabs, TheSlabHoldsItsDepth) {
    const DepthSlabs s(samples(64, 27.172, true));
    const std::vector<float> d = hard_depths(s);
    const int n = int(d.size());
    std::vector<int> k(n);
    std::vector<float> w(n);
    depth_cells(n, d.data(), s, k.data(), w.data());
    const float z_max = s.z.back();
    for (int u = 0; u < n; ++u) {
        const float zz = d[u] > 0.0f ? std::min(d[u], z_max) : z_max;
        ASSERT_GE(k[u], 0);
        ASSERT_LT(k[u], int(s.inv_h.size()));
        // one slab either way only where float rounding of the bucket puts the depth on an edge
        EXPECT_LE(s.z[k[u]], std::nextafter(zz, 1e30f)) << u;
        EXPECT_GE(s.z[k[u] + 1], std::nextafter(zz, 0.0f)) << u;
        EXPECT_GE(w[u], 0.0f);
        EXPECT_LE(w[u], 1.0f);
    }
}

}  // namespace
}  // namespace deepsea
