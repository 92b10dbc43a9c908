#pragma once
// Internal: vectorised per-row kernels, compiled with -ffast-math (kernels.cpp, lamps.cpp).
// Inputs must be sanitised first: open water is z == 0, never NaN or inf, because fast-math
// assumes finite values.

namespace deepsea::kernels {

/// Per pixel of a row: d2 = |P|, T = exp(-c d2), D = J/pi * E * T (0 for open water).
/// E is planar RGB irradiance; J, D, T interleaved RGB; d2 out.
void shade_row(int n, const float* x, const float* y, const float* z, const float* e_planar,
               const float* J, const float c[3], float* D, float* T, float* d2);

}  // namespace deepsea::kernels

namespace deepsea::kernels {

/// Per pixel of a row (interleaved RGB): w = exp(-G d2) - T for surfaces (0 for open water,
/// z == 0), F = w * blurred, final = D + F + B. blurred may be null (no forward scatter: F = 0).
void finish_row(int n, const float* z, const float* d2, const float G[3], const float* T,
                const float* blurred, const float* D, const float* B, float* F, float* final);

}  // namespace deepsea::kernels
