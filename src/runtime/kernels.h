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

/// One row's geometry from raw planar depth (any float: NaN, inf, <= 0 and sentinels are open
/// water, optics' has_surface, tested on the float's bits so that fast-math cannot drop it):
/// z sanitised (open water 0), the back-projected x = rx z and y = ry z, and, given the rows
/// above and below (`z_up`, `z_down` raw, or both null at the frame's first and last rows),
/// the normals by central differences in float. Sets irregular[u] = 1 where a neighbour is
/// open water or across a depth discontinuity (optics' same_surface), where u is the first or
/// last column, or everywhere without the rows around: the caller then uses the optics rule
/// (one-sided differences) for those pixels, whose n it leaves unwritten. One pass for what
/// took four (sanitising three rows and back-projecting one): the rows stay in L1.
void geometry_row(int n, const float* rx, float ry_up, float ry, float ry_down, const float* z_up,
                  const float* raw, const float* z_down, float* x, float* y, float* z, float* nx,
                  float* ny, float* nz, unsigned char* irregular);

}  // namespace deepsea::kernels

namespace deepsea::kernels {

/// The forward kernel's lean (optics/forward_lean.h) of a row's pixels, interleaved (lu, lv)
/// in lean[2u], lean[2u + 1]: rays (rx[u], ry, 1), normals nx, ny, nz (0: no surface).
void lean_row(int n, const float* rx, float ry, const float* nx, const float* ny, const float* nz,
              float fx, float fy, float* lean);

/// The largest of n values and 0 (a row's farthest surface; values never NaN).
float row_max(int n, const float* d);

/// Planar RGB rows scaled per pixel and added: out[c * n + u] += s[u] * part[c * n + u]
/// (first: written, out = s[u] * part[...], the same where s part is never -0). A tabulated
/// lamp's irradiance, part its terms with RID 1 and s its RID.
void add_scaled(int n, const float* s, const float* part, float* out, bool first);

/// Planar RGB (planes[c * n + u]) to interleaved rgb[3 * u + c].
void interleave(int n, const float* planes, float* rgb);

}  // namespace deepsea::kernels
