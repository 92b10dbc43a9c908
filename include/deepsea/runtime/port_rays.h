#pragma once
/// \file Rendering through the housing's port (docs/ports.md, "Rendering through a port"): each
/// output pixel's water-side ray, traced once per camera (like the camera stage's lens map), and
/// where it meets the surface of a frame's depth map.

#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/port.h"
#include "deepsea/optics/port_hit.h"

namespace deepsea {

/// The water-side rays of every pixel of one camera through one port. The camera is both the
/// output's (the pixel whose ray is traced through the port) and the input's (the RGB-D frame
/// is a pinhole view from the camera centre with the same intrinsics).
class PortRays {
public:
    /// Traces every pixel (trace_port). ConfigError naming camera.port where no pixel's ray
    /// sees the input (sees_input): nothing of the frame would be rendered. The port must have
    /// passed validate and check_port_view for this camera (every ray reaches the water).
    PortRays(const Port& port, const Camera& camera);

    /// One pixel's ray in float (the green channel's direction: the geometry of the hit; the
    /// other channels' differ by the water's dispersion, left out of where the ray lands).
    struct Ray {
        float ox, oy, oz;  ///< origin on the outer surface, metres
        float dx, dy, dz;  ///< unit direction in the water
        /// Its projection (optics' RayProjection), the vanishing point as an offset from (u, v)
        /// (float keeps it to 1e-5 px)
        float u_inf, v_inf, du, dv, s_origin;
        /// The march's per-ray constants (optics' PortMarch): the stretch of s in which the
        /// projection lies inside the input (empty: s_lo > s_hi), pixels per unit of s
        float s_lo, s_hi, rate;
    };

    const Port& port() const { return m_port; }
    const Camera& camera() const { return m_camera; }
    const Ray& ray(int u, int v) const { return m_rays[std::size_t(v) * m_camera.width + u]; }
    /// The ray's projection in double, as find_port_hit takes it.
    RayProjection projection(int u, int v) const;
    /// What optics' march_port_ray takes of the ray, in float (the compositor's rows).
    PortMarch<float> march(int u, int v) const {
        const Ray& r = ray(u, v);
        return {
            float(u) + r.u_inf, float(v) + r.v_inf, r.du, r.dv, r.s_origin, r.s_lo, r.s_hi, r.rate};
    }
    /// Row v's march constants in float, one array per field (what march() gives each pixel but
    /// its rate, max(|du|, |dv|), which the rows take from du and dv: float's rounding keeps the
    /// order, so it is march()'s bit for bit), and its rays' planar origin depth oz and direction
    /// dz (ray()'s): the path to a hit at planar depth z is (z - oz) / dz. Nothing else: the hit
    /// point's x and y come from where it projects (docs/ports.md, "Speed"), so that a frame reads
    /// 9 floats per pixel of the rays, not 14.
    struct MarchRow {
        const float *u_inf, *v_inf, *du, *dv, *s_origin, *s_lo, *s_hi, *oz, *dz;
    };
    static constexpr int kMarchRowFields = 9;
    MarchRow march_row(int v) const {
        const std::size_t n = m_rays.size();
        const float* f = m_march_soa.data() + std::size_t(v) * m_camera.width;
        return {f,         f + n,     f + 2 * n, f + 3 * n, f + 4 * n,
                f + 5 * n, f + 6 * n, f + 7 * n, f + 8 * n};
    }
    /// march_row(v) for marches that start at s <= s_near (the compositor's rows: 1.001 / z_near,
    /// z_near the frame's nearest surface). Where every ray of the row has s_near <= s_origin and
    /// s_near <= s_hi (its march starts in front of its origin and of its view's near end) and
    /// s_lo = 0 (it sees the input up to its vanishing point), as behind an ordinary flat port,
    /// the march takes the same values from rows of constants (s_lo 0, s_origin and s_hi +inf:
    /// each min with them picks what it picks with the true values, or an equal float), which
    /// stay in cache, instead of three planes of the table; and where every ray's oz has the same
    /// bits (a flat port facing along the axis: its outer surface is the plane z = distance +
    /// glass_thickness), oz from a row of that value: the rows read 5 floats a ray, not 9.
    MarchRow march_row(int v, float s_near) const;
    /// Where pixel (u, v)'s ray meets the frame's surface, given its inverse planar depth
    /// (optics' inverse_depth) and nearest surface depth z_near (+inf: no surface): the float
    /// march of the compositor's rows (march_port_ray, from port_start_s where
    /// port_start_window allows, the window's nearest surface read here pixel by pixel), its
    /// hit in double.
    PortHit hit(int u, int v, const Image& inv_depth, double z_near) const;
    /// Pixels per radian of the water-side rays at the image centre, along x: fx without a port,
    /// about n_water / n_air times fx behind a flat one. The forward blur's angular scale.
    double water_fx() const { return m_water_fx; }
    /// The input pixels that the rays' marches at inverse depths s <= s_max (the march's start
    /// and a thousandth beyond it) and their taps can read, inclusive: a box over the vanishing
    /// points and the projections' largest rates, with a margin of 3 pixels for float's rounding
    /// (the whole image where a projection is not finite). The compositor makes the input's
    /// normals and colour only there (docs/ports.md, "Speed").
    struct PixelBox {
        int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
    };
    PixelBox reach(double s_max) const;
    /// Per pixel, port_radiance_factor: water-side radiance to the radiance reaching the camera
    /// (the n^2 law, with Fresnel on request), RGB.
    const Image& radiance_factor() const { return m_factor; }

private:
    Port m_port;
    Camera m_camera;
    std::vector<Ray> m_rays;
    std::vector<float> m_march_soa;  ///< march_row's fields, width x height planes each
    /// Per row: the least s_origin and s_hi (NaN if any is), whether every s_lo is +0; and the
    /// rows of constants for march_row(v, s_near) (width floats each)
    std::vector<float> m_row_hi;
    std::vector<char> m_row_lo_zero;
    std::vector<float> m_zero_row, m_inf_row;
    std::vector<float> m_oz_row;  ///< every ray's oz where they all have the same bits, else empty
    double m_water_fx = 0.0;
    /// reach()'s bounds: the vanishing points' box (input pixels) and the largest |du|, |dv|
    double m_u_lo = 0.0, m_u_hi = 0.0, m_v_lo = 0.0, m_v_hi = 0.0, m_du = 0.0, m_dv = 0.0;
    Image m_factor;
};

/// The nearest surface depth of a planar depth image (+inf where it has none).
double nearest_surface(const Image& depth);

/// The nearest surface of each window of optics' port_start_window: the largest value of the
/// inverse depth image `inv` over the 3 x 3 blocks of kPortStartBlock pixels around each block,
/// into `out` (resized: one value a block; `scratch` holds each block's own). Where a ray's
/// march may start (port_start_s).
void window_nearest(const Image& inv, Image& out, Image& scratch);

/// window_nearest in two steps, so that the compositor takes the first in its pass over the
/// frame's rows: one row of `inv` (W values), each block's largest value (ceil(W /
/// kPortStartBlock) of them, into `out`); then from those of every row (`rows`: one row each),
/// window_nearest's `out` (`scratch` as there).
void window_row_maxima(const float* inv, int W, float* out);
void window_nearest_rows(const Image& rows, Image& out, Image& scratch);

}  // namespace deepsea
