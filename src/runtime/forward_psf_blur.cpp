#include "deepsea/runtime/forward_psf_blur.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "clones.h"
#include "column_basis.h"
#include "deepsea/core/error.h"
#include "deepsea/core/fast_math.h"
#include "deepsea/optics/lamp.h"
#include "deepsea/optics/transmission.h"
#include "forward_psf_rows.h"
#include "gaussian_planes.h"

namespace deepsea {

using psf_rows::add_doubled;
using psf_rows::block_rows;
using psf_rows::doubled_row;
using psf_rows::expand_blocks;
using psf_rows::f_row;
using psf_rows::kMaxStride;
using psf_rows::padded_rgb_row;
using psf_rows::padded_row;
using psf_rows::pair_sums;
using psf_rows::RowTaps;
using psf_rows::weigh_block_pairs;
using psf_rows::weigh_blocks;

namespace {

constexpr int kTableBins = 1024;
/// What the weight basis may leave out of any scale's weight, as a fraction of the channel's
/// largest total weight: far below a 16-bit code value of the forward-scatter image.
constexpr double kBasisTolerance = 1e-6;
/// The same for weights from a transport table: its Monte Carlo error is 0.1-5 % of a depth's
/// light, and weights linear between 32 depths are far from the few smooth functions the
/// small-angle model's are (spanning them to 1e-6 took every scale, and 50 % more time).
constexpr double kTableBasisTolerance = 1e-3;

/// Table rows and fractions of one row of distances,
///   d_u / step = i_u + t_u,  i_u = min(floor(d_u / step), bins - 1),
/// and idx[u] = -1 where there is no surface (d <= 0) or the distance is beyond the table (its
/// weights are negligible). Returns the number of surfaces beyond the table. AVX2 without fused
/// multiply-adds (t_u from the rounded product, as in the generic clone).
DEEPSEA_CLONES_NO_FMA
int table_rows(int n, const float* __restrict d2, float inv_step, float range, int bins,
               int* __restrict idx, float* __restrict frac) {
    int beyond = 0;
#pragma omp simd reduction(+ : beyond)
    for (int u = 0; u < n; ++u) {
        const float d = d2[u];
        const bool on = d > 0.0f && d < range;
        const float ti = on ? d * inv_step : 0.0f;
        const int i = std::min(int(ti), bins - 1);
        idx[u] = on ? i : -1;
        frac[u] = ti - float(i);
        beyond += d >= range ? 1 : 0;
    }
    return beyond;
}

}  // namespace

ForwardPsfBlur::ForwardPsfBlur(ForwardPsf psf, const Rgb& c) : m_psf(std::move(psf)), m_c(c) {
    if (m_psf.scales() > kMaxStride) throw ConfigError("forward scatter: too many scales");
}

double ForwardPsfBlur::table_span(int rung) { return std::pow(2.0, 0.25 * rung); }

void ForwardPsfBlur::use_table(int rung) {
    if (rung == m_rung) return;
    if (m_rung >= 0) {
        m_kept[m_rung] = {m_step,
                          m_bins,
                          m_stride,
                          m_lanes,
                          std::move(m_table),
                          std::move(m_coef),
                          std::move(m_sharp)};
    }
    m_rung = rung;
    const auto it = m_kept.find(rung);
    if (it == m_kept.end()) {
        build_table(table_span(rung));
        return;
    }
    KeptTable& k = it->second;
    m_step = k.step;
    m_bins = k.bins;
    m_stride = k.stride;
    m_lanes = k.lanes;
    m_table = std::move(k.table);
    m_coef = std::move(k.coef);
    m_sharp = std::move(k.sharp);
    m_kept.erase(it);
}

void ForwardPsfBlur::build_table(double d_max) {
    const int S = m_psf.scales(), blurred = S - 1;
    m_bins = kTableBins;
    m_step = d_max / m_bins;
    const int rows = m_bins + 1;
    // Every scale's weight at every table distance, in double: w[(c * S + j) * rows + i].
    std::vector<double> w(std::size_t(3) * S * rows);
    tbb::parallel_for(0, rows, [&](int i) {
        for (int j = 0; j < S; ++j) {
            const Rgb x = m_psf.weight(j, i * m_step);
            for (int c = 0; c < 3; ++c) w[(std::size_t(c) * S + j) * rows + i] = x[c];
        }
    });
    // W_0(d), then W_0(d) + exp(-c d): the unblurred scale with the direct signal's
    // transmission (add_direct_row: D + F's unblurred part is L (T + W_0), one table).
    m_sharp.assign(std::size_t(rows) * 8, 0.0f);
    for (int i = 0; i < rows; ++i) {
        const Rgb T = transmission(m_c, i * m_step);
        for (int c = 0; c < 3; ++c) {
            const double w0 = w[std::size_t(c) * S * rows + i];
            m_sharp[std::size_t(i) * 4 + c] = float(w0);
            m_sharp[(std::size_t(rows) + i) * 4 + c] = float(w0 + T[c]);
        }
    }
    // The blurred scales' weights are smooth in distance and nearly dependent (the same few
    // scattering orders mixed in different proportions): a few basis functions per channel
    // span them to kBasisTolerance of the channel's largest total, and pixels are weighed by
    // those instead of by every scale.
    std::array<ColumnBasis, 3> basis;
    int rank = 1;
    for (int c = 0; c < 3; ++c) {
        const auto first = w.begin() + (std::ptrdiff_t(c) * S + 1) * rows;
        const std::vector<double> cols(first, first + std::ptrdiff_t(blurred) * rows);
        double total = 0.0;
        for (int i = 0; i < rows; ++i) {
            double sum = 0.0;
            for (int j = 0; j < blurred; ++j) sum += cols[std::size_t(j) * rows + i];
            total = std::max(total, sum);
        }
        const double tol = m_psf.from_transport() ? kTableBasisTolerance : kBasisTolerance;
        basis[c] = span_columns(cols, rows, blurred, tol * total);
        rank = std::max(rank, basis[c].rank);
    }
    m_stride = rank <= 20 ? (rank + 3) / 4 * 4 : kMaxStride;
    m_lanes = 3 * m_stride;
    m_table.assign(std::size_t(rows) * m_lanes, 0.0f);
    m_coef.assign(std::size_t(3) * S * m_stride, 0.0f);
    for (int c = 0; c < 3; ++c) {
        const ColumnBasis& b = basis[c];
        for (int r = 0; r < b.rank; ++r) {
            for (int i = 0; i < rows; ++i) {
                m_table[std::size_t(i) * m_lanes + c * m_stride + r] =
                    float(b.basis[std::size_t(r) * rows + i]);
            }
            for (int j = 1; j < S; ++j) {
                m_coef[(std::size_t(c) * S + j) * m_stride + r] =
                    float(b.coef[std::size_t(j - 1) * b.rank + r]);
            }
        }
    }
}

Rgb ForwardPsfBlur::applied_weight(int j, double d) const {
    Rgb out;
    if (m_table.empty() || !(d >= 0.0) || d >= m_bins * m_step) return out;
    const int i = std::min(int(d / m_step), m_bins - 1);
    const double t = d / m_step - i;
    const int S = m_psf.scales();
    for (int c = 0; c < 3; ++c) {
        auto lerp_at = [&](const float* row0, int stride) {
            return row0[0] + t * (row0[stride] - row0[0]);
        };
        if (j == 0) {
            out[c] = lerp_at(m_sharp.data() + std::size_t(i) * 4 + c, 4);
            continue;
        }
        double sum = 0.0;
        for (int r = 0; r < m_stride; ++r) {
            sum += m_coef[(std::size_t(c) * S + j) * m_stride + r] *
                   lerp_at(m_table.data() + std::size_t(i) * m_lanes + c * m_stride + r, m_lanes);
        }
        out[c] = sum;
    }
    return out;
}

void ForwardPsfBlur::resize(int W, int H) {
    m_width = W;
    m_height = H;
    m_groups.clear();
    m_levels.assign(m_psf.scales() - 1, Level{});
    for (int j = 1; j < m_psf.scales(); ++j) {
        const int f = level_factor(m_psf.sigma_px(j), W, H);
        if (m_groups.empty() || m_groups.back().factor != f) {
            Group g;
            g.factor = f;
            g.j0 = j;
            g.w = (W + f - 1) / f;
            g.h = (H + f - 1) / f;
            m_groups.push_back(std::move(g));
        }
        m_groups.back().j1 = j + 1;
        Level& L = m_levels[j - 1];
        L.group = int(m_groups.size()) - 1;
        const Group& g = m_groups.back();
        L.planes.assign(std::size_t(3) * g.w * g.h, 0.0f);
    }
    // Scales blurred at full resolution (only on images under 16 px a side) add up here.
    m_full.clear();
    if (!m_groups.empty() && m_groups.front().factor == 1)
        m_full.assign(std::size_t(3) * W * H, 0.0f);
    for (Group& g : m_groups) g.spent = resampling_variance(g.factor);
    m_grids.clear();
    const int f_max = m_groups.empty() ? 1 : m_groups.back().factor;
    for (int f = 2; f <= f_max; f *= 2) {
        Grid G;
        G.factor = f;
        G.w = (W + f - 1) / f;
        G.h = (H + f - 1) / f;
        G.acc.assign(std::size_t(3) * G.w * G.h, 0.0f);
        m_grids.push_back(std::move(G));
    }
    build_warp();
}

void ForwardPsfBlur::weigh(const Image& surface, const Image& d2) {
    const int W = m_width, H = m_height, lanes = m_lanes, stride = m_stride;
    const int S = m_psf.scales();
    const float inv_step = float(1.0 / m_step);
    const float range = float(m_bins * m_step);
    // A pyramid of block sums, one level per factor from the finest blocks (two pixels unless
    // a group needs single pixels, on tiny images) to the widest group's: each level's block
    // row is summed over its rows (the finest) or from the two block rows below it (pairs of
    // neighbouring blocks), and expanded into the levels' planes of its group, if it has one.
    const int f0 = m_groups.empty() || m_groups[0].factor == 1 ? 1 : 2;
    const int f_max = m_groups.empty() ? 1 : m_groups.back().factor;
    std::vector<int> group_at;       // group_at[i]: the group of level i's factor, or -1
    std::vector<std::size_t> at{0};  // where level i's block sums start in a task's buffer
    for (int f = f0; f <= f_max; f *= 2) {
        int k = -1;
        for (std::size_t g = 0; g < m_groups.size(); ++g)
            if (m_groups[g].factor == f) k = int(g);
        group_at.push_back(k);
        at.push_back(at.back() + std::size_t((W + f - 1) / f) * lanes);
    }
    // Bands of rows as high as the widest group's blocks, so that every block is summed by
    // one task, straight into its level's planes.
    tbb::parallel_for(0, (H + f_max - 1) / f_max, [&](int t) {
        thread_local std::vector<int> idx, idx_b, bi;
        thread_local std::vector<float> frac, frac_b, bt, sums;
        thread_local std::vector<float*> dst;
        idx.resize(W);
        frac.resize(W);
        idx_b.resize(W);
        frac_b.resize(W);
        bi.resize(W / 2 + 1);
        bt.resize(W / 2 + 1);
        sums.resize(at.back());
        for (int v = t * f_max; v < std::min(H, (t + 1) * f_max); ++v) {
            // Block distances: the finest level's blocks (2 x 2) weighed from two rows at once,
            // at even rows; the odd row below then has its blocks complete.
            const bool pairs = f0 == 2 && m_block_tol >= 0.0f && v % 2 == 0 && v + 1 < H;
            const bool paired = f0 == 2 && m_block_tol >= 0.0f && v % 2 == 1;
            if (!pairs && !paired)
                table_rows(W, d2.row(v), inv_step, range, m_bins, idx.data(), frac.data());
            int f = f0;
            for (std::size_t i = 0; i < group_at.size(); ++i, f *= 2) {
                // level i takes a block row of level i - 1 (this image row for the finest)
                // when that one is complete; the first it takes starts its sums
                const bool first = i == 0 ? v % f == 0 : v % f < f / 2;
                float* acc = sums.data() + at[i];
                if (i == 0 && pairs) {
                    // the rows' own table positions only where some block needs them
                    if (block_rows(W / 2, d2.row(v), d2.row(v + 1), inv_step, range, m_bins,
                                   m_block_tol, bi.data(), bt.data()) > 0 ||
                        W % 2) {
                        table_rows(W, d2.row(v), inv_step, range, m_bins, idx.data(), frac.data());
                        table_rows(W, d2.row(v + 1), inv_step, range, m_bins, idx_b.data(),
                                   frac_b.data());
                    }
                    weigh_block_pairs(W, stride, idx.data(), frac.data(), idx_b.data(),
                                      frac_b.data(), bi.data(), bt.data(), m_table.data(),
                                      surface.row(v), surface.row(v + 1), acc);
                } else if (i == 0 && paired) {
                    // summed with the row above
                } else if (i == 0) {
                    weigh_blocks(W, f, stride, idx.data(), frac.data(), m_table.data(),
                                 surface.row(v), !first, acc);
                } else {
                    pair_sums((W + f / 2 - 1) / (f / 2), stride, sums.data() + at[i - 1], !first,
                              acc);
                }
                const int rows = v % f + 1;
                if (rows != f && v != H - 1) break;  // coarser levels wait for this one
                if (group_at[i] < 0) continue;
                const Group& g = m_groups[group_at[i]];
                const int y = v / f, scales = g.j1 - g.j0;
                dst.resize(std::size_t(3) * scales);
                for (int c = 0; c < 3; ++c) {
                    for (int j = g.j0; j < g.j1; ++j) {
                        dst[c * scales + (j - g.j0)] =
                            m_levels[j - 1].planes.data() + (std::size_t(c) * g.h + y) * g.w;
                    }
                }
                const float scale = 1.0f / float(f * rows);
                const float edge = float(f) / float(W - (g.w - 1) * f);  // last block's columns
                expand_blocks(g.w, stride, scales, acc, m_coef.data() + std::size_t(g.j0) * stride,
                              std::size_t(S) * stride, dst.data(), scale, edge);
            }
        }
    });
}

void ForwardPsfBlur::prepare(const Image& surface, const Image& d2, const EdgeFalloff* beyond,
                             double farthest, const Image* lean) {
    const int W = surface.width, H = surface.height;
    // The frame's farthest surface, but no farther than where every weight is below 1e-17 of
    // a surface's radiance.
    double d_frame = farthest;
    if (d_frame < 0.0) {
        d_frame = tbb::parallel_reduce(
            tbb::blocked_range<int>(0, H), 0.0,
            [&](const tbb::blocked_range<int>& r, double m) {
                for (int v = r.begin(); v < r.end(); ++v) {
                    const float* d = d2.row(v);
                    for (int u = 0; u < W; ++u) m = std::max(m, double(d[u]));
                }
                return m;
            },
            [](double a, double b) { return std::max(a, b); });
    }
    // The table spans the first length of a fixed ladder (1 m, then steps of 2^(1/4)) beyond
    // this frame's farthest surface, so that a frame's F depends on that frame alone, never on
    // the frames a renderer saw before it (a resumed or sharded sequence gives the same bits).
    const double d_max = std::min(d_frame, m_psf.negligible_beyond());
    int rung = 0;
    while (table_span(rung) <= d_max) ++rung;
    use_table(rung);
    if (m_width != W || m_height != H) resize(W, H);

    weigh(surface, d2);
    m_surface = &surface;
    m_d2 = &d2;
    m_lean = m_psf.from_transport() && lean && lean->width == W && lean->height == H &&
                     lean->channels == 2
                 ? lean
                 : nullptr;
    if (m_lean) {
        m_full_mom.assign(m_full.size(), 0.0f);
        for (Grid& G : m_grids) G.mom.assign(G.acc.size(), 0.0f);
    }

    // Each scale's blur at its group's grid, added into that grid (or the full-resolution sum):
    // box downsampling and the upsampling cascade spread the light already
    // (resampling_variance); the Gaussian supplies the rest.
    std::fill(m_full.begin(), m_full.end(), 0.0f);
    for (Grid& G : m_grids) std::fill(G.acc.begin(), G.acc.end(), 0.0f);
    m_faded_group = -1;
    m_unblurred = 0;
    for (std::size_t i = 0; i < m_levels.size(); ++i) {
        Level& L = m_levels[i];
        const Group& g = m_groups[L.group];
        const double sigma = m_psf.sigma_px(int(i) + 1);
        const double rest = std::sqrt(std::max(sigma * sigma - g.spent, 0.09)) / g.factor;
        float* sum = g.factor == 1 ? m_full.data() : grid_of(g.factor).acc.data();
        // (the wide scales at true angles: in the equidistant image, set_camera)
        const bool warped = m_warp > 0 && g.factor >= m_warp;
        const float* src =
            warped ? warp_level(L.planes, g.factor, g.w, g.h, beyond) : L.planes.data();
        // The 1 px scale: box downsampling by two and the upsampling back spread its variance
        // already; the rest, 0.15 cells, would move each value by 1e-9 of its neighbours'.
        if (m_identity_blurs && !m_lean && !warped && rest < planes::kIdentitySigma) {
            planes::add_planes(std::size_t(3) * g.w * g.h, src, sum);
            ++m_unblurred;
            continue;
        }
        // Beyond the frame: a transport table's scene continues as its borders (its wide
        // scales reach across small images), fading as `beyond` says (lamp-lit scenes are
        // dimmer outside than in); the small-angle model's as the in-image mean, as it always
        // has.
        planes::Fade fade;
        if (m_psf.from_transport() && beyond && beyond->width == m_width &&
            beyond->height == m_height && beyond->samples() > 0) {
            fade.reach = planes::radius(rest);
            if (warped) {
                fade.reach = fade_equidistant(beyond, L.group);
            } else {
                fade_grid(*beyond, g.factor, g.w, g.h, fade.reach);
            }
            fade.left = m_fade[0].data();
            fade.right = m_fade[1].data();
            fade.top = m_fade[2].data();
            fade.bottom = m_fade[3].data();
        }
        const planes::Edge edge =
            m_psf.from_transport() ? planes::Edge::Clamp : planes::Edge::Normalise;
        if (!m_lean) {
            planes::blur_planes(planes::planar(src, g.w, g.h), sum, rest, m_kernel, m_norm_x,
                                m_norm_y, planes::Store::Add, edge,
                                fade.reach > 0 ? &fade : nullptr);
            continue;
        }
        // with a lean, each level's blur also into its grid's moments, times sigma^2
        const std::size_t n = std::size_t(3) * g.w * g.h;
        m_blurred.resize(n);
        planes::blur_planes(planes::planar(src, g.w, g.h), m_blurred.data(), rest, m_kernel,
                            m_norm_x, m_norm_y, planes::Store::Set, edge,
                            fade.reach > 0 ? &fade : nullptr);
        float* mom = g.factor == 1 ? m_full_mom.data() : grid_of(g.factor).mom.data();
        add_level(n, m_blurred.data(), float(sigma * sigma), sum, mom);
    }

    // Coarse to fine: each grid holds its own scales plus the next coarser grid upsampled
    // (carried beyond its outer cells where the scene continues: doubled_row).
    const bool extend = m_psf.from_transport();
    for (int k = int(m_grids.size()) - 2; k >= 0; --k) {
        Grid& G = m_grids[k];
        const Grid& coarser = m_grids[k + 1];
        if (m_warp > 0 && 2 * G.factor == m_warp) {
            add_unwarped(G, coarser);
            continue;
        }
        tbb::parallel_for(0, 3 * G.h, [&](int prow) {
            const int c = prow / G.h, y = prow % G.h;
            const RowTaps t = doubled_row(y, coarser.h, extend);
            const float* plane = coarser.acc.data() + std::size_t(c) * coarser.w * coarser.h;
            thread_local std::vector<float> padded;
            padded.resize(coarser.w + 2);
            padded_row(coarser.w, plane + std::size_t(t.y0) * coarser.w,
                       plane + std::size_t(t.y1) * coarser.w, t.w, 1, extend, padded.data());
            add_doubled(G.w, padded.data(), G.acc.data() + std::size_t(prow) * G.w);
            if (!m_lean) return;
            const float* mp = coarser.mom.data() + std::size_t(c) * coarser.w * coarser.h;
            padded_row(coarser.w, mp + std::size_t(t.y0) * coarser.w,
                       mp + std::size_t(t.y1) * coarser.w, t.w, 1, extend, padded.data());
            add_doubled(G.w, padded.data(), G.mom.data() + std::size_t(prow) * G.w);
        });
    }
    if (m_lean) add_lean();
}

ForwardPsfBlur::Grid& ForwardPsfBlur::grid_of(int factor) {
    for (Grid& G : m_grids)
        if (G.factor == factor) return G;
    throw Error("forward scatter: no grid of factor " + std::to_string(factor));
}

void ForwardPsfBlur::rgb_row(int v, float* out, bool add, bool direct) const {
    const int W = m_width, H = m_height;
    thread_local std::vector<float> frac, coarse;
    thread_local std::vector<int> idx;
    idx.resize(W);
    frac.resize(W);
    const int beyond = table_rows(W, m_d2->row(v), float(1.0 / m_step), float(m_bins * m_step),
                                  m_bins, idx.data(), frac.data());
    const float* full[3] = {};
    for (int c = 0; c < 3 && !m_full.empty(); ++c)
        full[c] = m_full.data() + (std::size_t(c) * H + v) * W;
    if (!m_grids.empty()) {
        // The factor-2 grid's row at v: its two grid rows blended, interleaved and padded.
        const Grid& G = m_grids[0];
        const bool extend = m_psf.from_transport();
        const RowTaps t = doubled_row(v, G.h, extend);
        coarse.resize(4 * std::size_t(G.w + 2));
        const float *r0[3], *r1[3];
        for (int c = 0; c < 3; ++c) {
            const float* plane = G.acc.data() + std::size_t(c) * G.w * G.h;
            r0[c] = plane + std::size_t(t.y0) * G.w;
            r1[c] = plane + std::size_t(t.y1) * G.w;
        }
        padded_rgb_row(G.w, r0, r1, t.w, extend, coarse.data());
    }
    const float* sharp = m_sharp.data() + (direct ? std::size_t(m_bins + 1) * 4 : 0);
    f_row(W, idx.data(), frac.data(), sharp, m_surface->row(v), m_full.empty() ? nullptr : full,
          m_grids.empty() ? nullptr : coarse.data(), add, out);
    if (!direct || beyond == 0) return;
    // Surfaces beyond the table (no forward scatter worth a table row): D alone, exactly.
    const float* d2 = m_d2->row(v);
    const float* L = m_surface->row(v);
    for (int u = 0; u < W; ++u) {
        if (idx[u] >= 0 || !(d2[u] > 0.0f)) continue;
        for (int c = 0; c < 3; ++c) {
            out[3 * u + c] +=
                direct_signal(L[3 * u + c], transmission<FastMath>(float(m_c[c]), d2[u]));
        }
    }
}

void ForwardPsfBlur::row(int v, float* out_rgb) const { rgb_row(v, out_rgb, false, false); }

void ForwardPsfBlur::add_row(int v, float* sum_rgb) const { rgb_row(v, sum_rgb, true, false); }

void ForwardPsfBlur::add_direct_row(int v, float* sum_rgb) const {
    rgb_row(v, sum_rgb, true, true);
}

}  // namespace deepsea
