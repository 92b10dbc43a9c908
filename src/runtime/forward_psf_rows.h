#pragma once
// Internal to the runtime: the row kernels of the forward scatter from the phase function
// (forward_psf_blur.cpp drives them). Each has an AVX2 clone (clones.h), declared only where
// it is defined: callers call the plain name, which the loader resolves to a clone.
//
// Together they evaluate docs/model.md's forward scatter from the phase function,
//   F = sum_j G_(sigma_j) * (W_j(d) L_s),   W_j(d) ~= sum_r a_jr phi_r(d)  (column_basis.h),
// L_s = J/pi E the surface radiance (`L`, interleaved RGB), d = d2 the camera-to-surface
// distance, phi_r(d) the few functions of distance that span the blurred scales' weights
// (`tab`, per channel), a_jr their coefficients (`coef`), W_0 the unblurred scale's weight
// (`sharp`). i_u, t_u: the table row and fraction of pixel u's distance (idx, frac).

#include <cstddef>

namespace deepsea::psf_rows {

/// Basis functions per channel in a table row, padded to a multiple of 4 (at most one per
/// blurred scale: 32 holds images of up to 2^30 px a side).
inline constexpr int kMaxStride = 32;

/// Upsampling by two, as the grids are built: output column (or row) x samples the grid twice
/// as coarse at (x + 0.5) / 2 - 0.5, its ends as padded_row says. That is 3/4 of the way from
/// column x/2 - 1 to x/2 for even x, 1/4 from (x - 1)/2 to (x + 1)/2 for odd x. With the
/// coarse row padded (one column at each end: qp[j + 1] = q[j]), output x reads qp at
/// x/2 + (x odd) and the next, edges included, without branches or gathers.

/// The two coarse rows that full row y samples, and the weight of the second (upsampling by
/// two, as add_doubled). Clamped at the grid's edges, or with `extend` the outer rows' line
/// carried a quarter cell beyond them (a scene that continues beyond the frame is blurred
/// there too: held flat, the outer half-cell of every grid took its neighbour's light inward).
struct RowTaps {
    int y0, y1;
    float w;
};
RowTaps doubled_row(int y, int h_lo, bool extend);

/// A coarse row between rows r0 and r1 (n cells), r0 + w (r1 - r0), every `lanes`-th float of
/// padded from padded[lanes] on, padded at each end for add_doubled: its outer cell repeated,
/// or with `extend` its outer pair's line continued one cell (see doubled_row); light carried
/// beyond the grid's cells (w outside [0, 1], or the ends with `extend`) is held >= 0.
void padded_row(int n, const float* r0, const float* r1, float w, int lanes, bool extend,
                float* padded);

/// padded_row of three planes at once (r0[c], r1[c]: plane c's two rows), interleaved: cell x's
/// RGB and a zero at padded[4 (x + 1)], the same values as padded_row with lanes 4.
void padded_rgb_row(int n, const float* const* r0, const float* const* r1, float w, bool extend,
                    float* padded);

/// dst[x] += the padded coarse row qp upsampled at x, for n columns.
void add_doubled(int n, const float* qp, float* dst);

/// x[b * lanes + c * stride + r] = (or, with add, +=) the sum over the block's pixels u (b * block
/// .. b * block + block - 1, fewer at the end) of phi_r(d_u) L_u[c], phi_r from the table's rows
/// idx[u] and idx[u] + 1 interpolated by frac[u]; pixels with idx[u] < 0 (no surface) add nothing.
void weigh_blocks(int n, int block, int stride, const int* idx, const float* frac, const float* tab,
                  const float* L, bool add, float* x);

/// Block distances of two rows of distances da, db, blocks of two columns: for each of the
/// `blocks` whole blocks b whose four distances are on the table (0 < d < range) and within
/// tol of its nearest (max - min <= tol min), the table row and fraction of its mean distance
/// (bi[b], bt[b]: as table_rows' with inv_step and bins); bi[b] = -1 for the others. Returns
/// the number of those, which weigh_block_pairs weighs pixel by pixel.
int block_rows(int blocks, const float* da, const float* db, float inv_step, float range, int bins,
               float tol, int* bi, float* bt);

/// weigh_blocks for blocks of two columns over two rows a and b (radiance La, Lb), the block
/// sums complete (not added): a block with bi[b] >= 0 (block_rows) once, at its mean distance,
/// times its pixels' summed radiance; any other block (and the last column of an odd n) pixel
/// by pixel from the rows' table rows and fractions ia, fa, ib, fb (table_rows; read only
/// there), as weigh_blocks over row a and then row b.
void weigh_block_pairs(int n, int stride, const int* ia, const float* fa, const int* ib,
                       const float* fb, const int* bi, const float* bt, const float* tab,
                       const float* La, const float* Lb, float* x);

/// One row of a group's planes from its blocks' basis sums: for every block b, channel c and
/// scale j of the group, dst[c * scales + j][b] = scale * sum_r coef[c * channel + j * stride
/// + r] * acc[b * lanes + c * stride + r], the last block also times `edge` (coef: the
/// group's first scale in the weight table's coefficients, `channel` floats per channel).
void expand_blocks(int n, int stride, int scales, const float* acc, const float* coef,
                   std::size_t channel, float* const* dst, float scale, float edge);

/// Sums of neighbouring blocks: dst block i = (or, with add, +=) src blocks 2i and 2i + 1 (the
/// last alone when n is odd), each block 3 * stride floats (a table row's lanes).
void pair_sums(int n, int stride, const float* src, bool add, float* dst);

/// Interleaved RGB F of one row: out[3u + c] = (or +=) W_0(d_u) L_u[c] (0 where idx[u] < 0) +
/// full[c][u] (when full is not null) + the factor-2 grid's row upsampled at u (when coarse is
/// not null). coarse: that grid's row blended between its two grid rows (doubled_row), padded
/// as add_doubled's, 4 floats a column (RGB and padding). A pixel's weights are a vector, four
/// pixels' twelve floats are three (whole vectors loaded and stored: a vector a pixel would
/// overlap the last store and stall).
void f_row(int n, const int* idx, const float* frac, const float* sharp, const float* L,
           const float* const* full, const float* coarse, bool add, float* out);

}  // namespace deepsea::psf_rows
