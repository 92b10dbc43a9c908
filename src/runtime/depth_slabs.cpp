// Hot loop: compiled with -ffast-math (see CMakeLists.txt); depth arrives sanitised (open water
// z == 0, never NaN or inf), as the compositor guarantees.

#include "depth_slabs.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "clones.h"

namespace deepsea {

namespace {

/// Buckets of at most the thinnest slab's thickness, so a bucket's slab is right or one short.
int bucket_count(const std::vector<double>& z) {
    double thinnest = z.back();
    for (std::size_t k = 0; k + 1 < z.size(); ++k) thinnest = std::min(thinnest, z[k + 1] - z[k]);
    const double n = std::ceil(z.back() / thinnest) + 1.0;
    return int(std::clamp(n, 1024.0, double(1 << 20)));
}

typedef float Float8 __attribute__((vector_size(32)));
typedef int Int8 __attribute__((vector_size(32)));

/// Pixel u's slab and weight, the definition (depth_cells_each).
[[gnu::always_inline]] inline void cell(float zu, const float* __restrict zs,
                                        const float* __restrict znext,
                                        const float* __restrict inv_h, const int* __restrict bucket,
                                        int last_bucket, float bucket_scale, float z_max,
                                        int& k_out, float& wz_out) {
    const float zz = zu > 0.0f ? std::min(zu, z_max) : z_max;
    int k = bucket[std::min(int(zz * bucket_scale), last_bucket)];
    k += znext[k] <= zz ? 1 : 0;
    k_out = k;
    wz_out = std::clamp((zz - zs[k]) * inv_h[k], 0.0f, 1.0f);
}

}  // namespace

DepthSlabs::DepthSlabs(const std::vector<double>& zd) {
    const int K = int(zd.size()) - 1;
    z.assign(zd.begin(), zd.end());
    inv_h.resize(K);
    znext.resize(K);
    for (int k = 0; k < K; ++k) {
        inv_h[k] = float(1.0 / (zd[k + 1] - zd[k]));
        znext[k] = k + 1 < K ? float(zd[k + 1]) : std::numeric_limits<float>::max();
    }
    const int buckets = bucket_count(zd);
    bucket_scale = float(buckets / zd.back());
    bucket.resize(buckets + 1);
    first.assign(K, buckets + 1);
    last.assign(K, -1);
    for (int b = 0, k = 0; b <= buckets; ++b) {
        const double zb = b / double(bucket_scale);
        while (k < K - 1 && zd[k + 1] <= zb) ++k;
        bucket[b] = k;
        first[k] = std::min(first[k], b);
        last[k] = b;
    }
}

void depth_cells_each(int n, const float* z, const DepthSlabs& s, int* k, float* wz) {
    const int last_bucket = int(s.bucket.size()) - 1;
    for (int u = 0; u < n; ++u) {
        cell(z[u], s.z.data(), s.znext.data(), s.inv_h.data(), s.bucket.data(), last_bucket,
             s.bucket_scale, s.z.back(), k[u], wz[u]);
    }
}

DEEPSEA_CLONES
void depth_cells(int n, const float* __restrict z, const DepthSlabs& s, int* __restrict k_out,
                 float* __restrict wz_out) {
    const float* __restrict zs = s.z.data();
    const float* __restrict znext = s.znext.data();
    const float* __restrict inv_h = s.inv_h.data();
    const int* __restrict bucket = s.bucket.data();
    const int last_bucket = int(s.bucket.size()) - 1, K = int(s.inv_h.size());
    const float z_max = s.z.back();
    const Float8 zmax8 = Float8{} + z_max, scale8 = Float8{} + s.bucket_scale;
    const Int8 last8 = Int8{} + last_bucket;
    int u = 0;
    for (; u + 8 <= n; u += 8) {
        Float8 zu;
        std::memcpy(&zu, z + u, sizeof zu);
        // as cell(): std::min(z, z_max) is z_max < z ? z_max : z
        const Float8 zz = zu > 0.0f ? (zmax8 < zu ? zmax8 : zu) : zmax8;
        Int8 b = __builtin_convertvector(zz * scale8, Int8);
        b = last8 < b ? last8 : b;
        const int k0 = bucket[b[0]];
        const Int8 outside = (b < s.first[k0]) | (b > s.last[k0]);
        int any = 0;
        for (int j = 0; j < 8; ++j) any |= outside[j];
        if (any) {
            for (int j = 0; j < 8; ++j) {
                cell(z[u + j], zs, znext, inv_h, bucket, last_bucket, s.bucket_scale, z_max,
                     k_out[u + j], wz_out[u + j]);
            }
            continue;
        }
        // every bucket's slab is k0: k0 + 1 where z_(k0 + 1) <= z'
        const int k1 = std::min(k0 + 1, K - 1);
        const Int8 up = Float8{} + znext[k0] <= zz;  // -1 or 0
        const Float8 z0 = up ? Float8{} + zs[k1] : Float8{} + zs[k0];
        const Float8 h = up ? Float8{} + inv_h[k1] : Float8{} + inv_h[k0];
        Float8 w = (zz - z0) * h;
        w = w < 0.0f ? 0.0f : w;  // as std::clamp
        w = 1.0f < w ? 1.0f : w;
        const Int8 k = k0 - up;
        std::memcpy(k_out + u, &k, sizeof k);
        std::memcpy(wz_out + u, &w, sizeof w);
    }
    for (; u < n; ++u) {
        cell(z[u], zs, znext, inv_h, bucket, last_bucket, s.bucket_scale, z_max, k_out[u],
             wz_out[u]);
    }
}

}  // namespace deepsea
