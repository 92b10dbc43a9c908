#pragma once
// Internal: vectorised per-row kernels, compiled with -ffast-math (kernels.cpp, lamps.cpp).
// Inputs must be sanitised first: open water is z == 0, never NaN or inf, because fast-math
// assumes finite values.

namespace deepsea::kernels {

/// Per pixel of a row: d2 = |P| (0 for open water, where P = 0) and the surface radiance
/// L = J/pi * E (lamp.h's lambertian_radiance; 0 for open water). E is planar RGB
/// irradiance; J, L interleaved RGB.
void shade_row(int n, const float* x, const float* y, const float* z, const float* e_planar,
               const float* J, float* d2, float* L);

/// Per pixel of a row (interleaved RGB), surfaces where d2 > 0: T = exp(-c d2), the direct
/// signal D = L * T (all 0 for open water), and final += D (final holds B on entry). c3 holds
/// c[k % 3] at k (3n floats); dx is scratch of 3n floats. T and D null: final += D only.
void direct_row(int n, const float* d2, const float* c3, const float* L, float* dx, float* T,
                float* D, float* final);

}  // namespace deepsea::kernels

namespace deepsea::kernels {

/// Per pixel of a row (interleaved RGB), surfaces where d2 > 0: w = exp(-G d2) - exp(-c d2),
/// F = w * blurred (0 for open water), and final += F (final holds B + D on entry). With G
/// null, blurred is F itself, on open water too (the phase-function point spread, weighed
/// before the blur).
void forward_row(int n, const float* d2, const float c[3], const float G[3], const float* blurred,
                 float* F, float* final);

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

/// The forward kernel's lean (optics/forward_lean.h) of a row's pixels, interleaved (lu, lv)
/// in lean[2u], lean[2u + 1]: rays (rx[u], ry, 1), normals nx, ny, nz (0: no surface).
void lean_row(int n, const float* rx, float ry, const float* nx, const float* ny, const float* nz,
              float fx, float fy, float* lean);

/// The largest of n values and 0 (a row's farthest surface; values never NaN).
float row_max(int n, const float* d);

/// Planar RGB (planes[c * n + u]) to interleaved rgb[3 * u + c].
void interleave(int n, const float* planes, float* rgb);

}  // namespace deepsea::kernels
