#pragma once
// Internal: vectorised per-row kernels, compiled with -ffast-math (kernels.cpp, lamps.cpp).
// Inputs must be sanitised first: open water is z == 0, never NaN or inf, because fast-math
// assumes finite values.

namespace deepsea::kernels {

/// Per pixel of a row: d2 = |P| (0 for open water, where P = 0), D = J/pi * E * exp(-c d2)
/// (0 for open water). E is planar RGB irradiance; J, D interleaved RGB; d2 out. If L is not
/// null it receives the surface radiance J/pi * E (interleaved), what forward scatter blurs.
void shade_row(int n, const float* x, const float* y, const float* z, const float* e_planar,
               const float* J, const float c[3], float* D, float* d2, float* L = nullptr);

}  // namespace deepsea::kernels

namespace deepsea::kernels {

/// Per pixel of a row (interleaved RGB), surfaces where d2 > 0: T = exp(-c d2),
/// w = exp(-G d2) - T, F = w * blurred (all 0 for open water), and final += F (final holds
/// B + D on entry). blurred may be null (no forward scatter: F = 0); with G null, blurred is F
/// itself, on open water too (the phase-function point spread, weighed before the blur).
void finish_row(int n, const float* d2, const float c[3], const float G[3], const float* blurred,
                float* T, float* F, float* final);

}  // namespace deepsea::kernels

namespace deepsea::kernels {

/// Normals of one interior row by central differences, in float. z rows are sanitised (open
/// water 0). Writes n and sets irregular[u] = 1 where a neighbour is open water or across a
/// depth discontinuity (optics' same_surface), or where u is the first or last column: the
/// caller then uses the optics rule (one-sided differences) for those pixels.
void normals_row(int n, const float* rx, float ry_up, float ry, float ry_down, const float* z_up,
                 const float* z, const float* z_down, float* nx, float* ny, float* nz,
                 unsigned char* irregular);

}  // namespace deepsea::kernels

namespace deepsea::kernels {

/// Planar RGB (planes[c * n + u]) to interleaved rgb[3 * u + c].
void interleave(int n, const float* planes, float* rgb);

}  // namespace deepsea::kernels
