#pragma once
// Internal: adaptive Gauss-Kronrod (7-15) quadrature of vector-valued integrands.

#include <cmath>

namespace deepsea::detail {

// Kronrod nodes (positive half, the last is 0) and weights; Gauss weights for the 7-point
// rule on the odd-indexed Kronrod nodes.
// clang-format off
inline constexpr double kXgk[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
inline constexpr double kWgk[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
inline constexpr double kWg[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};
// clang-format on

/// One GK15 panel on [a, b] of f (returns T with +, * by double, and per-component abs via
/// `absdiff`). Writes the Kronrod value and |Kronrod - Gauss|.
template <class T, class F, class AbsDiff>
void gk15(const F& f, double a, double b, T& kronrod, T& error, const AbsDiff& absdiff) {
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    const T fc = f(c);
    T k = fc * kWgk[7];
    T g = fc * kWg[3];
    for (int j = 0; j < 7; ++j) {
        const double x = h * kXgk[j];
        const T f1 = f(c - x), f2 = f(c + x);
        const T s = f1 + f2;
        k = k + s * kWgk[j];
        if (j % 2 == 1) g = g + s * kWg[j / 2];
    }
    kronrod = k * h;
    error = absdiff(kronrod, g * h);
}

}  // namespace deepsea::detail
