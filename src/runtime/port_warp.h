#pragma once
// Internal: the compositor's rows through a port (docs/ports.md, "Rendering through a port").

#include "deepsea/core/image.h"
#include "deepsea/runtime/port_rays.h"

namespace deepsea {

/// The input's per-pixel normals, inverse depth and linear colour as the port's rows read them:
/// 8 floats per pixel, (nx, ny, nz, 1 / z, r, g, b, 0), so that a tap is two 4-float loads (the
/// inverse depth beside the normal: the march's last probe reads it with the normal's taps).
inline constexpr int kPortSurfaceChannels = 8;

/// One input row's depth for the port's rows, from its sanitised planar depth z (open water 0):
/// its inverse depth (optics' inverse_depth: 1 / z, 0 for open water) and the largest inverse
/// depth of each run of kPortStartBlock pixels (window_row_maxima). Returns the row's nearest
/// surface (its smallest z > 0; +inf without one).
float port_depth_row(int W, const float* z, float* inv, float* window_row);

/// n pixels of an input row's interleaved surface (kPortSurfaceChannels) from their normals,
/// inverse depth (port_depth_row's) and linear colour (interleaved RGB).
void port_surface_row(int n, const float* nx, const float* ny, const float* nz, const float* J,
                      const float* inv, float* surface);

/// The inverse depths of n rays' 2 x 2 cells (at[u] = y0 W + x0, x0 <= W - 2, y0 <= H - 2, in an
/// image W pixels wide): c0, c1 the pixels (x0, y0) and (x0 + 1, y0), c2, c3 the row below. With
/// AVX2 two 8-byte loads a lane (port_cells.cpp), the same floats.
void gather_cells(int n, const int* at, const float* inv, int W, float* c0, float* c1, float* c2,
                  float* c3);

/// One output row's surface through the port (inv_depth: the frame's inverse_depth; nearest: its
/// window_nearest, where each ray's march may start; surface: its rows by port_surface_row, whose
/// inverse depth must be inv_depth's): for each pixel
/// u of row v, where its water-side ray meets the frame (optics' march_port_ray, in float): the hit
/// point P (camera frame; 0 for open water and unseen), the water-side path t from the port to it
/// (0 without a hit), the normal and the colour there (interleaved RGB; both 0 without a hit) from
/// the input's per-pixel normals and linear colour (`surface`, kPortSurfaceChannels), taken as
/// optics' surface_taps says (bilinear on one surface, nearest across an edge; the normal
/// renormalised), and the mask: 1 where the input shows what the ray meets (a surface or open
/// water), 0 where it does not (PortHitKind::Unseen).
struct PortRow {
    float *x, *y, *z, *t, *nx, *ny, *nz, *J, *mask;
};
void port_row(const PortRays& rays, int v, const Image& inv_depth, const Image& nearest,
              const Image& surface, double z_near, const PortRow& out);

}  // namespace deepsea
