#pragma once
// Internal: the compositor's rows through a port (docs/ports.md, "Rendering through a port").

#include "deepsea/core/image.h"
#include "deepsea/runtime/port_rays.h"

namespace deepsea {

/// The input's per-pixel normals and linear colour as the port's rows read them: 8 floats per
/// pixel, (nx, ny, nz, 0, r, g, b, 0), so that a tap is two 4-float loads.
inline constexpr int kPortSurfaceChannels = 8;

/// One output row's surface through the port (inv_depth: the frame's inverse_depth; nearest: its
/// window_nearest, where each ray's march may start): for each pixel
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
