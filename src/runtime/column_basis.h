#pragma once
// Internal to the runtime: a few sampled functions that span many others (the forward
// scatter's per-scale weights, which are smooth in distance and nearly linearly dependent),
// so that a hot loop weighs every pixel by the few and recovers the many from block sums.

#include <vector>

namespace deepsea {

/// columns[j * rows + i] ~= sum_r basis[r * rows + i] coef[j * rank + r], every entry within
/// the tolerance it was built with. The basis is orthonormal; linear interpolation between
/// rows commutes with the sum, so interpolated columns are recovered as well.
struct ColumnBasis {
    int rows = 0, cols = 0, rank = 0;
    std::vector<double> basis;  ///< rank x rows
    std::vector<double> coef;   ///< cols x rank
};

/// Gram-Schmidt with column pivoting (the column with the largest residual joins the basis
/// next, orthogonalised twice) until no entry of any column's residual exceeds `tol`
/// (absolute). rank <= min(rows, cols); all-zero columns give rank 0.
ColumnBasis span_columns(const std::vector<double>& columns, int rows, int cols, double tol);

}  // namespace deepsea
