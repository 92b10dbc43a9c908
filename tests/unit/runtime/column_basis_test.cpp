// The weight basis of the forward scatter (column_basis.h) by its properties: columns that are
// combinations of a few functions need exactly those few, every column comes back within the
// tolerance asked, and the basis is orthonormal.

#include "column_basis.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace deepsea {
namespace {

/// The largest |columns - basis * coef| over every entry.
double worst_error(const std::vector<double>& columns, const ColumnBasis& b) {
    double worst = 0.0;
    for (int j = 0; j < b.cols; ++j) {
        for (int i = 0; i < b.rows; ++i) {
            double x = 0.0;
            for (int r = 0; r < b.rank; ++r) {
                x += b.basis[std::size_t(r) * b.rows + i] * b.coef[std::size_t(j) * b.rank + r];
            }
            worst = std::max(worst, std::abs(x - columns[std::size_t(j) * b.rows + i]));
        }
    }
    return worst;
}

/// columns[j * rows + i] = f(i, j).
template <class F>
std::vector<double> tabulate(int rows, int cols, F f) {
    std::vector<double> m(std::size_t(rows) * cols);
    for (int j = 0; j < cols; ++j)
        for (int i = 0; i < rows; ++i) m[std::size_t(j) * rows + i] = f(i, j);
    return m;
}

TEST(ColumnBasis, CombinationsOfTwoFunctionsNeedTwo) {
    const int rows = 200, cols = 9;
    const std::vector<double> m = tabulate(rows, cols, [](int i, int j) {
        const double d = 0.05 * i;
        return (j + 1) * std::exp(-0.3 * d) - 0.5 * j * d * std::exp(-d);
    });
    const ColumnBasis b = span_columns(m, rows, cols, 1e-12);
    EXPECT_EQ(b.rank, 2);
    EXPECT_LE(worst_error(m, b), 1e-12);
    // orthonormal
    for (int r = 0; r < b.rank; ++r) {
        for (int s = 0; s < b.rank; ++s) {
            double dot = 0.0;
            for (int i = 0; i < rows; ++i) {
                dot += b.basis[std::size_t(r) * rows + i] * b.basis[std::size_t(s) * rows + i];
            }
            EXPECT_NEAR(dot, r == s ? 1.0 : 0.0, 1e-12) << r << ", " << s;
        }
    }
}

TEST(ColumnBasis, EveryColumnComesBackWithinTheTolerance) {
    // Poisson-mixed exponentials, like the forward scatter's weights: nearly dependent, so a
    // looser tolerance needs fewer functions, and each meets its own bar.
    const int rows = 500, cols = 12;
    const std::vector<double> m = tabulate(rows, cols, [](int i, int j) {
        const double bd = 0.02 * i;
        double term = std::exp(-1.5 * bd), sum = 0.0;
        for (int n = 1; n < 30; ++n) {
            term *= bd / n;
            sum += term * std::exp(-0.3 * std::abs(n - j));
        }
        return sum;
    });
    int last_rank = 0;
    for (const double tol : {1e-3, 1e-6, 1e-9, 1e-12}) {
        const ColumnBasis b = span_columns(m, rows, cols, tol);
        EXPECT_LE(worst_error(m, b), tol) << "tolerance " << tol;
        EXPECT_GE(b.rank, last_rank);
        EXPECT_LE(b.rank, cols);
        last_rank = b.rank;
    }
    EXPECT_LT(span_columns(m, rows, cols, 1e-6).rank, cols);
}

TEST(ColumnBasis, ZeroColumnsNeedNothingAndIndependentOnesNeedAll) {
    const int rows = 6, cols = 4;
    EXPECT_EQ(span_columns(std::vector<double>(rows * cols, 0.0), rows, cols, 0.0).rank, 0);
    std::vector<double> identity(rows * cols, 0.0);
    for (int j = 0; j < cols; ++j) identity[std::size_t(j) * rows + j] = 1.0;
    const ColumnBasis b = span_columns(identity, rows, cols, 0.0);
    EXPECT_EQ(b.rank, cols);
    EXPECT_LE(worst_error(identity, b), 1e-15);
}

}  // namespace
}  // namespace deepsea
