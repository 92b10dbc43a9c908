#pragma once
// Internal to the runtime: the backscatter lookup's last step (asset_backscatter.cpp), one image
// row's B from its blended slice, each pixel's lattice columns and its depth slab.

namespace deepsea {

/// An image row's lattice columns as the lookup reads them: per pixel the offsets of its two
/// lattice columns in the slice and the second's weight; spans: runs of pixels between the
/// same two columns, span s ending (exclusive) at span_end[s], the first starting at pixel 0.
struct LookupColumns {
    const int* col0;
    const int* col1;
    const float* colw;
    const int* span_end;
    int spans;
};

/// B for n pixels of one image row, interleaved RGB out: linear between the two lattice
/// columns of each pixel and between the samples of its slab k_u (weight wz_u),
///   B(u) = L(L(S_i0[k], S_i0[k + 1], wz_u), L(S_i1[k], S_i1[k + 1], wz_u), w_u),
/// L(a, b, w) = a + w (b - a), S_i[k] the three floats at slice + col_i + 3 k (the slice has a
/// float of room at its end: a sample is read as four floats). Eight pixels of one span and
/// one slab (a smooth surface's common case) share their four samples: those are laid out
/// once in the order of the eight pixels' 24 interleaved values, and the eight take three
/// vectors of arithmetic. The same operations on each value as lookup_row_pairs: the same bits.
void lookup_row(int n, const float* slice, const LookupColumns& cols, const int* slab,
                const float* wz, float* out);

/// The same, two pixels to an eight-lane vector whatever their slabs (the definition the
/// grouped form is tested against, and its path for groups that span two slabs).
void lookup_row_pairs(int n, const float* slice, const int* col0, const int* col1,
                      const float* colw, const int* slab, const float* wz, float* out);

}  // namespace deepsea
