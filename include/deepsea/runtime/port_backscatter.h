#pragma once
/// \file Backscatter through a port from an asset baked along pinhole rays (docs/ports.md,
/// "Rendering through a port"): each water-side ray is looked up along the pinhole column of
/// the same direction, over the stretch of that column beside the water-side path.

#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/runtime/port_rays.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

/// The water light along each pixel's water-side ray X(t) = o + t w, t from 0 (the port's outer
/// surface) to the hit, from a pinhole asset: the asset's column through the vanishing point of
/// w (bilinear, as AssetBackscatter) between the path lengths s0 = o . w and s0 + t along it,
///   B = exp(c s0) [B_asset(col(w), (s0 + t) w.z) - B_asset(col(w), s0 w.z)]:
/// the parallel pinhole ray over the same stretch, displaced sideways by o - (o . w) w, its
/// light attenuated back to the port only (exp(c s0) undoes the asset's path from the camera
/// centre: the housing holds no water). Exact
/// (to the lattice's interpolation) for a dome with the camera at its centre, where o lies on
/// the pinhole ray; for other ports the displacement's error is measured in docs/ports.md.
/// backscatter_row takes each pixel's hit as planar depth of the hit point (0: open water, which
/// looks up z_max as the asset does).
class PortBackscatter final : public BackscatterSource {
public:
    /// The rays' camera must see what the asset's does (check_camera). Both must outlive this.
    PortBackscatter(const Asset& asset, const PortRays& rays);
    void backscatter_row(int v, int n, const float* z, float* out_rgb) const override;

private:
    /// One channel triple of the column blend at asset depth z.
    void lookup(int pixel, float z, float* out) const;

    const Asset& m_asset;
    const PortRays& m_rays;
    struct Column {
        int base;       ///< offset of the (i0, j0) column's first sample
        int di, dj;     ///< offsets to the (i1, .) and (., j1) columns
        float wi, wj;   ///< weights of i1 and j1
        float z_off;    ///< s0 w.z - o.z: asset depth = hit's planar depth + z_off
        float b0[3];    ///< B at the path's start, s0 w.z
        float gain[3];  ///< exp(c s0): the asset attenuates back to the camera centre
    };
    std::vector<Column> m_columns;
    std::vector<float> m_z;  ///< the asset's depth samples
};

}  // namespace deepsea
