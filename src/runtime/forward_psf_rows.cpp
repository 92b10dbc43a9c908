// The forward scatter's row kernels (forward_psf_rows.h). Hot loops: compiled with
// -ffast-math -fopenmp-simd (see CMakeLists.txt).

#include "forward_psf_rows.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "clones.h"
#include "float4.h"

// (f_row's Float8 values live in registers inside it, its lambdas inlined: no call passes one,
// so GCC's note that AVX changes the ABI of such calls does not apply to its generic clone)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace deepsea::psf_rows {

namespace {

/// An empty asm that GCC must assume reads and changes v: a sum before it is not
/// reassociated with one after it.
[[gnu::always_inline]] inline void opaque(Float4& v) {
#if defined(__x86_64__) || defined(__i386__)
    asm("" : "+x"(v));
#elif defined(__aarch64__)
    asm("" : "+w"(v));
#else
    (void)v;
#endif
}

/// Kernel::run<S>(args...) for a table stride S known at compile time: 4, 8, 12, 16, 20, or
/// kMaxStride for anything else (inlined into each caller, and so into its AVX2 clone).
template <class Kernel, class... Args>
[[gnu::always_inline]] inline void by_stride(int stride, Args... args) {
    switch (stride) {
        case 4:
            return Kernel::template run<4>(args...);
        case 8:
            return Kernel::template run<8>(args...);
        case 12:
            return Kernel::template run<12>(args...);
        case 16:
            return Kernel::template run<16>(args...);
        case 20:
            return Kernel::template run<20>(args...);
        default:
            return Kernel::template run<kMaxStride>(args...);
    }
}

/// weigh_blocks for a stride S known at compile time: the weighing in basis form, for every
/// block b (its pixels u in B_b), channel c and basis function r,
///   x_b[c][r] (+)= sum_(u in B_b) phi_r(d_u) L_s(u)[c],
///   phi_r(d_u) = tab[i_u][c][r] + t_u (tab[i_u + 1][c][r] - tab[i_u][c][r])  (0 off surfaces),
/// so that sum_r a_jr x_b[c][r] = sum_(u in B_b) W_j(d_u) L_s(u)[c] for every scale j. A
/// block's sums stay in registers, four basis functions to a vector: S is a multiple of four.
struct WeighBlocks {
    template <int S>
    [[gnu::always_inline]] static void run(int n, int block, const int* __restrict idx,
                                           const float* __restrict frac,
                                           const float* __restrict tab, const float* __restrict L,
                                           bool add, float* __restrict x) {
        constexpr int lanes = 3 * S, V = S / 4;
        for (int u0 = 0, b = 0; u0 < n; u0 += block, ++b) {
            Float4 acc[3 * V] = {};
            for (int u = u0; u < std::min(u0 + block, n); ++u) {
                const bool on = idx[u] >= 0;
                const float* ta = tab + std::size_t(on ? idx[u] : 0) * lanes;
                const float* tb = ta + lanes;
                const float t = frac[u];
                for (int c = 0; c < 3; ++c) {
                    const float l = on ? L[3 * u + c] : 0.0f;
                    for (int k = 0; k < V; ++k) {
                        const Float4 a = load4(ta + c * S + 4 * k),
                                     d = load4(tb + c * S + 4 * k) - a;
                        acc[c * V + k] += (a + t * d) * l;
                    }
                }
            }
            float* out = x + std::size_t(b) * lanes;
            for (int k = 0; k < 3 * V; ++k)
                store4(out + 4 * k, add ? load4(out + 4 * k) + acc[k] : acc[k]);
        }
    }
};

/// weigh_blocks over two rows (a, b) at once, blocks of two columns (the finest level, factor
/// 2), with block distances (block_rows): a block on one smooth surface is weighed at its mean
/// distance dbar_b,
///   x_b[c][r] = phi_r(dbar_b) sum_(u in B_b) L_s(u)[c],
/// one table row for four pixels (docs/model.md, "Forward scatter": within 0.1 % of the forward
/// layer's maximum); other blocks pixel by pixel as weigh_blocks sums them (row a, then row b
/// added: the same bits).
struct WeighBlockPairs {
    template <int S>
    [[gnu::always_inline]] static void run(int n, const int* __restrict ia,
                                           const float* __restrict fa, const int* __restrict ib,
                                           const float* __restrict fb, const int* __restrict bi,
                                           const float* __restrict bt, const float* __restrict tab,
                                           const float* __restrict La, const float* __restrict Lb,
                                           float* __restrict x) {
        constexpr int lanes = 3 * S, V = S / 4;
        // one pixel's basis weights times its radiance, added to acc (weigh_blocks' sum)
        const auto add_pixel = [&](Float4* acc, int i, float t, const float* l) {
            const bool on = i >= 0;
            const float* ta = tab + std::size_t(on ? i : 0) * lanes;
            const float* tb = ta + lanes;
            for (int c = 0; c < 3; ++c) {
                const float lc = on ? l[c] : 0.0f;
                for (int k = 0; k < V; ++k) {
                    const Float4 a = load4(ta + c * S + 4 * k), d = load4(tb + c * S + 4 * k) - a;
                    acc[c * V + k] += (a + t * d) * lc;
                }
            }
        };
        // whole blocks before the row's last one, whose radiance loads would pass the row's end
        const int safe = n / 2 - 1;
        const auto sum4 = [](const float* p) {  // RGB of the two pixels at p, lanes 0-2
            return Float4{p[0] + p[3], p[1] + p[4], p[2] + p[5], 0.0f};
        };
        for (int u0 = 0, b = 0; u0 < n; u0 += 2, ++b) {
            float* out = x + std::size_t(b) * lanes;
            if (b < n / 2 && bi[b] >= 0) {
                // the block's summed radiance in lanes 0-2: pixel u0's RGB plus u0 + 1's
                const float* la = La + 3 * u0;
                const float* lb = Lb + 3 * u0;
                const Float4 l = b < safe
                                     ? (load4(la) + load4(la + 3)) + (load4(lb) + load4(lb + 3))
                                     : sum4(la) + sum4(lb);
                const float* ta = tab + std::size_t(bi[b]) * lanes;
                const float* tb = ta + lanes;
                const float t = bt[b];
                if constexpr (S == 4) {
                    // the twelve lanes as eight and four (each lane's arithmetic as below)
                    const Float8 a8 = load8(ta), d8 = load8(tb) - a8;
                    const Float8 l8 = __builtin_shufflevector(l, l, 0, 0, 0, 0, 1, 1, 1, 1);
                    const Float8 x8 = (a8 + t * d8) * l8;
                    std::memcpy(out, &x8, sizeof x8);
                    const Float4 a4 = load4(ta + 8), d4 = load4(tb + 8) - a4;
                    store4(out + 8, (a4 + t * d4) * splat(l[2]));
                    continue;
                }
                for (int c = 0; c < 3; ++c) {
                    const Float4 lc = splat(l[c]);
                    for (int k = 0; k < V; ++k) {
                        const Float4 a = load4(ta + c * S + 4 * k),
                                     d = load4(tb + c * S + 4 * k) - a;
                        store4(out + c * S + 4 * k, (a + t * d) * lc);
                    }
                }
                continue;
            }
            const int u1 = std::min(u0 + 2, n);
            Float4 acc_a[3 * V] = {}, acc_b[3 * V] = {};
            for (int u = u0; u < u1; ++u) add_pixel(acc_a, ia[u], fa[u], La + 3 * u);
            for (int u = u0; u < u1; ++u) add_pixel(acc_b, ib[u], fb[u], Lb + 3 * u);
            for (int k = 0; k < 3 * V; ++k) store4(out + 4 * k, acc_a[k] + acc_b[k]);
        }
    }
};

/// expand_blocks for a stride S known at compile time: each scale's block mean from the basis
/// sums, for scale j of the group, channel c and block b,
///   P_j[c][b] = s_b sum_r a_jr[c] x_b[c][r] = s_b sum_(u in B_b) W_j(d_u) L_s(u)[c],
/// s_b = scale = 1 / (f rows) (times edge for the last block, which has fewer columns): the
/// box-downsampled W_j(d) L_s that G_(sigma_j) then blurs on this grid.
struct ExpandBlocks {
    template <int S>
    [[gnu::always_inline]] static void run(int n, int scales, const float* __restrict acc,
                                           const float* __restrict coef, std::size_t channel,
                                           float* const* dst, float scale, float edge) {
        constexpr int lanes = 3 * S, V = S / 4;
        for (int c = 0; c < 3; ++c) {
            for (int j = 0; j < scales; ++j) {
                const float* k = coef + c * channel + std::size_t(j) * S;
                Float4 kv[V];
                for (int i = 0; i < V; ++i) kv[i] = load4(k + 4 * i);
                float* __restrict out = dst[c * scales + j];
                const auto dot = [&](int b) {
                    const float* a = acc + std::size_t(b) * lanes + c * S;
                    Float4 s = kv[0] * load4(a);
                    for (int i = 1; i < V; ++i) s += kv[i] * load4(a + 4 * i);
                    return s;
                };
                int b = 0;
                for (; b + 4 <= n; b += 4) {
                    // four blocks' sums at once: their vectors transposed and added
                    const Float4 s0 = dot(b), s1 = dot(b + 1), s2 = dot(b + 2), s3 = dot(b + 3);
                    const Float4 u01 = __builtin_shufflevector(s0, s1, 0, 4, 1, 5) +
                                       __builtin_shufflevector(s0, s1, 2, 6, 3, 7);
                    const Float4 u23 = __builtin_shufflevector(s2, s3, 0, 4, 1, 5) +
                                       __builtin_shufflevector(s2, s3, 2, 6, 3, 7);
                    store4(out + b, (__builtin_shufflevector(u01, u23, 0, 1, 4, 5) +
                                     __builtin_shufflevector(u01, u23, 2, 3, 6, 7)) *
                                        scale);
                }
                for (; b < n; ++b) {
                    const Float4 s = dot(b);
                    out[b] = ((s[0] + s[2]) + (s[1] + s[3])) * scale;
                }
                out[n - 1] *= edge;
            }
        }
    }
};

}  // namespace

/// Bilinear upsampling by two, one grid row q into the next finer grid (the cascade):
///   dst[x] += q[i_x] + a_x (q[i_x + 1] - q[i_x]),  i_x = floor(p_x), a_x = p_x - i_x,
///   p_x = (x + 1/2) / 2 - 1/2,
/// so a_x = 3/4 for even x and 1/4 for odd x; qp[j + 1] = q[j], its ends from pad_ends.
RowTaps doubled_row(int y, int h_lo, bool extend) {
    const float fy = (y + 0.5f) / 2.0f - 0.5f;
    if (extend && h_lo > 1) {
        const int y0 = std::clamp(int(std::floor(fy)), 0, h_lo - 2);
        return {y0, y0 + 1, fy - float(y0)};
    }
    const int y0 = std::clamp(int(std::floor(fy)), 0, h_lo - 1);
    return {y0, std::min(y0 + 1, h_lo - 1), std::clamp(fy - y0, 0.0f, 1.0f)};
}

DEEPSEA_CLONES_NO_FMA
void padded_row(int n, const float* r0, const float* r1, float w, int lanes, bool extend,
                float* padded) {
    const bool beyond = w < 0.0f || w > 1.0f;
    if (lanes == 1) {  // the cascade's planes: one vector loop (no fused multiply-add)
#pragma omp simd
        for (int x = 0; x < n; ++x) {
            const float q = r0[x] + w * (r1[x] - r0[x]);
            padded[x + 1] = beyond ? std::max(0.0f, q) : q;
        }
    }
    for (int x = 0; x < n && lanes != 1; ++x) {
        const float q = r0[x] + w * (r1[x] - r0[x]);
        padded[std::size_t(x + 1) * lanes] = beyond ? std::max(0.0f, q) : q;
    }
    const float* first = padded + lanes;
    float* last = padded + std::size_t(n) * lanes;
    padded[0] = first[0];
    last[lanes] = last[0];
    if (extend && n > 1) {
        padded[0] = std::max(0.0f, 2.0f * first[0] - first[lanes]);
        last[lanes] = std::max(0.0f, 2.0f * last[0] - last[-lanes]);
    }
}

/// padded_row for the three planes of one grid into interleaved cells of four floats (RGB and
/// a zero), four cells at a time: each value's arithmetic is padded_row's (no fused
/// multiply-add, as in the generic code), so the bits are the same as three padded_row calls.
DEEPSEA_CLONES_NO_FMA
void padded_rgb_row(int n, const float* const* r0, const float* const* r1, float w, bool extend,
                    float* __restrict padded) {
    const bool beyond = w < 0.0f || w > 1.0f;
    const Float4 zero = {};
    const auto at = [&](int c, int x) {  // one plane's four cells from x on
        const Float4 a = load4(r0[c] + x), q = a + w * (load4(r1[c] + x) - a);
        return beyond ? max4(zero, q) : q;
    };
    int x = 0;
    for (; x + 4 <= n; x += 4) {
        const Float4 r = at(0, x), g = at(1, x), b = at(2, x);
        // [r0 g0 r1 g1] [r2 g2 r3 g3] [b0 0 b1 0] [b2 0 b3 0], then a cell each
        const Float4 rg01 = __builtin_shufflevector(r, g, 0, 4, 1, 5);
        const Float4 rg23 = __builtin_shufflevector(r, g, 2, 6, 3, 7);
        const Float4 b01 = __builtin_shufflevector(b, zero, 0, 4, 1, 5);
        const Float4 b23 = __builtin_shufflevector(b, zero, 2, 6, 3, 7);
        float* p = padded + 4 * std::size_t(x + 1);
        store4(p, __builtin_shufflevector(rg01, b01, 0, 1, 4, 5));
        store4(p + 4, __builtin_shufflevector(rg01, b01, 2, 3, 6, 7));
        store4(p + 8, __builtin_shufflevector(rg23, b23, 0, 1, 4, 5));
        store4(p + 12, __builtin_shufflevector(rg23, b23, 2, 3, 6, 7));
    }
    for (; x < n; ++x) {
        float* p = padded + 4 * std::size_t(x + 1);
        for (int c = 0; c < 3; ++c) {
            const float q = r0[c][x] + w * (r1[c][x] - r0[c][x]);
            p[c] = beyond ? std::max(0.0f, q) : q;
        }
        p[3] = 0.0f;
    }
    const float* first = padded + 4;
    float* last = padded + 4 * std::size_t(n);
    for (int c = 0; c < 4; ++c) {
        padded[c] = first[c];
        last[4 + c] = last[c];
        if (extend && n > 1) {
            padded[c] = std::max(0.0f, 2.0f * first[c] - first[4 + c]);
            last[4 + c] = std::max(0.0f, 2.0f * last[c] - last[c - 4]);
        }
    }
}

DEEPSEA_CLONES
void add_doubled(int n, const float* __restrict qp, float* __restrict dst) {
    const int pairs = n / 2;
#pragma omp simd
    for (int i = 0; i < pairs; ++i) {
        dst[2 * i] += qp[i] + 0.75f * (qp[i + 1] - qp[i]);
        dst[2 * i + 1] += qp[i + 1] + 0.25f * (qp[i + 2] - qp[i + 1]);
    }
    if (n % 2) dst[n - 1] += qp[pairs] + 0.75f * (qp[pairs + 1] - qp[pairs]);
}

DEEPSEA_CLONES
void weigh_blocks(int n, int block, int stride, const int* idx, const float* frac, const float* tab,
                  const float* L, bool add, float* x) {
    by_stride<WeighBlocks>(stride, n, block, idx, frac, tab, L, add, x);
}

/// Block distances of two rows (a, b), blocks of two columns: for every whole block b whose
/// four distances all lie on the table (0 < d < range) and on one smooth surface (max - min <=
/// tol min), its mean distance's table row and fraction (bi[b], bt[b]); bi[b] = -1 for any
/// other block, which is weighed pixel by pixel. Returns the number of those.
DEEPSEA_CLONES_NO_FMA
int block_rows(int blocks, const float* __restrict da, const float* __restrict db, float inv_step,
               float range, int bins, float tol, int* __restrict bi, float* __restrict bt) {
    int apart = 0;
#pragma omp simd reduction(+ : apart)
    for (int b = 0; b < blocks; ++b) {
        const float d0 = da[2 * b], d1 = da[2 * b + 1], d2 = db[2 * b], d3 = db[2 * b + 1];
        const float lo = std::min(std::min(d0, d1), std::min(d2, d3));
        const float hi = std::max(std::max(d0, d1), std::max(d2, d3));
        const bool same = lo > 0.0f && hi < range && hi - lo <= tol * lo;
        const float ti = 0.25f * ((d0 + d1) + (d2 + d3)) * inv_step;
        const int i = std::min(int(ti), bins - 1);
        bi[b] = same ? i : -1;
        bt[b] = ti - float(i);
        apart += same ? 0 : 1;
    }
    return apart;
}

DEEPSEA_CLONES
void weigh_block_pairs(int n, int stride, const int* ia, const float* fa, const int* ib,
                       const float* fb, const int* bi, const float* bt, const float* tab,
                       const float* La, const float* Lb, float* x) {
    by_stride<WeighBlockPairs>(stride, n, ia, fa, ib, fb, bi, bt, tab, La, Lb, x);
}

DEEPSEA_CLONES
void expand_blocks(int n, int stride, int scales, const float* acc, const float* coef,
                   std::size_t channel, float* const* dst, float scale, float edge) {
    by_stride<ExpandBlocks>(stride, n, scales, acc, coef, channel, dst, scale, edge);
}

/// Block sums of twice the width from the finer level's, every lane (c, r) alike:
///   x_(2f)[i] (+)= x_f[2i] + x_f[2i + 1]   (x_f[n - 1] alone when n is odd).
/// Lanes = 3 S known at compile time (by_stride), so that a block's few vectors are whole
/// loads and adds rather than a loop of runtime length, a fraction of a block long.
struct PairSums {
    template <int S>
    [[gnu::always_inline]] static void run(int n, const float* __restrict src, bool add,
                                           float* __restrict dst) {
        constexpr int lanes = 3 * S, V = S / 4;
        const int pairs = n / 2;
        for (int i = 0; i < pairs; ++i) {
            const float* s = src + std::size_t(2 * i) * lanes;
            float* d = dst + std::size_t(i) * lanes;
            for (int k = 0; k < 3 * V; ++k) {
                const Float4 s0 = load4(s + 4 * k), s1 = load4(s + lanes + 4 * k);
                if (!add) {
                    store4(d + 4 * k, s0 + s1);
                    continue;
                }
                // (d + s0) + s1, the order GCC gave the loop of runtime length this replaces
                // (-ffast-math would otherwise add s0 + s1 first: other bits)
                Float4 t = load4(d + 4 * k) + s0;
                opaque(t);
                store4(d + 4 * k, t + s1);
            }
        }
        if (n % 2) {
            const float* s = src + std::size_t(n - 1) * lanes;
            float* d = dst + std::size_t(pairs) * lanes;
            for (int k = 0; k < 3 * V; ++k)
                store4(d + 4 * k, add ? load4(d + 4 * k) + load4(s + 4 * k) : load4(s + 4 * k));
        }
    }
};

DEEPSEA_CLONES
void pair_sums(int n, int stride, const float* src, bool add, float* dst) {
    by_stride<PairSums>(stride, n, src, add, dst);
}

/// F of one full-resolution row, every term of the sum over scales:
///   F(u) (+)= W_0(d_u) L_s(u) + sum_(j at factor 1) (G_(sigma_j) * (W_j L_s))(u) + U(A_2)(u),
///   W_0(d_u) = sharp[i_u] + t_u (sharp[i_u + 1] - sharp[i_u])  (0 off surfaces),
/// the middle sum `full` (tiny images only), A_2 the factor-2 grid, which holds every coarser
/// scale blurred (the cascade), and U its upsampling by two as in add_doubled.
DEEPSEA_CLONES
void f_row(int n, const int* __restrict idx, const float* __restrict frac,
           const float* __restrict sharp, const float* __restrict L, const float* const* full,
           const float* __restrict coarse, bool add, float* __restrict out) {
    // One pixel's sum before L: its sharp weights (RGB, 0 where idx < 0) and its upsampled grid
    // value (the fourth lane padding).
    const auto weights = [&](int u) {
        const bool on = idx[u] >= 0;
        const float* ta = sharp + std::size_t(on ? idx[u] : 0) * 4;
        const Float4 a = load4(ta), b = load4(ta + 4);
        return on ? a + frac[u] * (b - a) : Float4{};
    };
    const auto grid = [&](int u) {
        const int odd = u & 1;
        const float* q = coarse + 4 * std::size_t((u >> 1) + odd);
        const Float4 q0 = load4(q), q1 = load4(q + 4);
        return q0 + (odd ? 0.25f : 0.75f) * (q1 - q0);
    };
    int u = 0;
    if (!full && coarse) {
        // Four pixels at a time, two to an eight-lane vector: each lane's arithmetic is that of
        // weights() and grid() (the same bits), their twelve interleaved floats stored as two
        // whole vectors. A pixel's sharp weights, where it has none, from a row of zeros.
        static const float zeros[8] = {};
        // (a pixel's two table rows are eight floats in a row: one load each, then the two
        // pixels' first rows and second rows paired; the fractions spread from one load)
        const auto weights2 = [&](int u, Float8 t) {
            const float* ta = idx[u] >= 0 ? sharp + std::size_t(idx[u]) * 4 : zeros;
            const float* tb = idx[u + 1] >= 0 ? sharp + std::size_t(idx[u + 1]) * 4 : zeros;
            const Float8 x = load8(ta), y = load8(tb);
            const Float8 a = __builtin_shufflevector(x, y, 0, 1, 2, 3, 8, 9, 10, 11);
            const Float8 b = __builtin_shufflevector(x, y, 4, 5, 6, 7, 12, 13, 14, 15);
            return a + t * (b - a);
        };
        // pixels u (even) and u + 1 read the padded grid at u/2, u/2 + 1 and u/2 + 2
        const Float8 quarter = {0.75f, 0.75f, 0.75f, 0.75f, 0.25f, 0.25f, 0.25f, 0.25f};
        const auto grid2 = [&](int u) {
            const float* q = coarse + 4 * std::size_t(u >> 1);
            const Float8 q0 = load8(q), q1 = load8(q + 4);
            return q0 + quarter * (q1 - q0);
        };
        for (; u + 4 <= n; u += 4) {
            const Float4 t = load4(frac + u);
            const Float8 w01 = weights2(u, __builtin_shufflevector(t, t, 0, 0, 0, 0, 1, 1, 1, 1));
            const Float8 w23 =
                weights2(u + 2, __builtin_shufflevector(t, t, 2, 2, 2, 2, 3, 3, 3, 3));
            const Float8 g01 = grid2(u), g23 = grid2(u + 2);
            // [r0 g0 b0 r1 g1 b1 r2 g2] [b2 r3 g3 b3]
            const Float8 wa = __builtin_shufflevector(w01, w23, 0, 1, 2, 4, 5, 6, 8, 9);
            const Float4 wc = __builtin_shufflevector(w23, w23, 2, 4, 5, 6);
            const Float8 ga = __builtin_shufflevector(g01, g23, 0, 1, 2, 4, 5, 6, 8, 9);
            const Float4 gc = __builtin_shufflevector(g23, g23, 2, 4, 5, 6);
            float* o = out + 3 * std::size_t(u);
            const float* l = L + 3 * std::size_t(u);
            const Float8 fa = wa * load8(l) + ga;
            const Float4 fc = wc * load4(l + 8) + gc;
            const Float8 sa = add ? load8(o) + fa : fa;
            std::memcpy(o, &sa, sizeof sa);
            store4(o + 8, add ? load4(o + 8) + fc : fc);
        }
    }
    for (; u < n; ++u) {
        const Float4 l = {L[3 * u], L[3 * u + 1], L[3 * u + 2], 0.0f};
        Float4 s = weights(u) * l;
        if (full) s += Float4{full[0][u], full[1][u], full[2][u], 0.0f};
        if (coarse) s += grid(u);
        for (int c = 0; c < 3; ++c) out[3 * u + c] = add ? out[3 * u + c] + s[c] : s[c];
    }
}

}  // namespace deepsea::psf_rows
