#include "column_basis.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace deepsea {

// Gram-Schmidt with column pivoting on the columns w_j (for the forward scatter, the blurred
// scales' weights W_j at the table's distances d_i):
//   residual  e_j = w_j - sum_r (b_r . w_j) b_r, over the basis so far;
//   pivot     p = argmax_j |e_j|^2 among the columns with max_i |e_j[i]| > tol;
//   new b_r   = q / |q|,  q = e_p - sum_r' (b_r' . e_p) b_r'  (orthogonalised a second time);
//   coef      a_jr = b_r . w_j, so that w_j ~= sum_r a_jr b_r (W_j(d) ~= sum_r a_jr phi_r(d)).
ColumnBasis span_columns(const std::vector<double>& columns, int rows, int cols, double tol) {
    ColumnBasis out;
    out.rows = rows;
    out.cols = cols;
    const std::size_t n = std::size_t(rows);
    std::vector<double> residual = columns;
    auto column = [&](std::vector<double>& m, int j) { return m.data() + std::size_t(j) * n; };
    auto worst_entry = [&](int j) {
        double m = 0.0;
        const double* r = column(residual, j);
        for (std::size_t i = 0; i < n; ++i) m = std::max(m, std::abs(r[i]));
        return m;
    };
    while (out.rank < std::min(rows, cols)) {
        int pivot = -1;
        double norm2 = 0.0;
        for (int j = 0; j < cols; ++j) {
            if (worst_entry(j) <= tol) continue;
            const double* r = column(residual, j);
            double s = 0.0;
            for (std::size_t i = 0; i < n; ++i) s += r[i] * r[i];  // |e_j|^2
            if (pivot < 0 || s > norm2) pivot = j, norm2 = s;
        }
        if (pivot < 0 || norm2 <= 0.0) break;
        // The new direction: the pivot's residual, orthogonalised against the basis once more
        // (the residual has lost accuracy to cancellation by now), then normalised.
        std::vector<double> q(column(residual, pivot), column(residual, pivot) + n);
        for (int r = 0; r < out.rank; ++r) {
            const double* b = out.basis.data() + std::size_t(r) * n;
            double dot = 0.0;
            for (std::size_t i = 0; i < n; ++i) dot += b[i] * q[i];
            for (std::size_t i = 0; i < n; ++i) q[i] -= dot * b[i];
        }
        double len = 0.0;
        for (const double x : q) len += x * x;
        len = std::sqrt(len);
        if (!(len > 0.0)) break;
        for (double& x : q) x /= len;
        out.basis.insert(out.basis.end(), q.begin(), q.end());
        ++out.rank;
        for (int j = 0; j < cols; ++j) {  // e_j -= (b_r . e_j) b_r
            double* r = column(residual, j);
            double dot = 0.0;
            for (std::size_t i = 0; i < n; ++i) dot += q[i] * r[i];
            for (std::size_t i = 0; i < n; ++i) r[i] -= dot * q[i];
        }
    }
    // Coefficients by projecting the original columns (not the accumulated residual updates).
    out.coef.assign(std::size_t(cols) * out.rank, 0.0);
    for (int j = 0; j < cols; ++j) {
        const double* w = columns.data() + std::size_t(j) * n;
        for (int r = 0; r < out.rank; ++r) {
            const double* b = out.basis.data() + std::size_t(r) * n;
            double dot = 0.0;
            for (std::size_t i = 0; i < n; ++i) dot += b[i] * w[i];
            out.coef[std::size_t(j) * out.rank + r] = dot;
        }
    }
    return out;
}

}  // namespace deepsea
