#pragma once
/// \file Backscatter from a baked asset: the runtime's lookup, with per-column and per-row
/// interpolation weights precomputed once per frame size.

#include <cstddef>
#include <memory>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/optics/camera.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

struct DepthSlabs;
struct BackscatterRowBounds;

/// Looks B(u, v, z) up in an asset for frames of `camera`: bilinear in (u, v), linear in z,
/// constant beyond z_max (also for open water). The camera must be the asset's or the same
/// view at another resolution (AssetError otherwise); pixel positions are then mapped through
/// the intrinsics. Same interpolation as Asset::sample (lattice.h's lattice_cell and lerp).
class AssetBackscatter final : public BackscatterSource {
public:
    AssetBackscatter(const Asset& asset, const Camera& camera);
    void backscatter_row(int v, int n, const float* z, float* out_rgb) const override;
    /// Pixel by pixel, the same interpolation as backscatter_row (within float rounding).
    void backscatter_pixels(int v, int n, const float* z, int count, const int* cols,
                            float* out_rgb) const override;
    /// The lattice's bounds for rows interpolated between looked-up rows (8 apart at the
    /// demo's focal length), to 5e-4 of B (docs/runtime.md, "Bounded approximations").
    const BackscatterRowBounds* row_bounds() const override { return m_row_bounds.get(); }

private:
    const Asset& m_asset;
    std::vector<LatticeCell<float>> m_rows;  ///< per image row: its two lattice rows
    /// Per image column: offsets of its two lattice columns in a row's slice (3 nk floats
    /// per column), and the weight of the second.
    std::vector<int> m_col0, m_col1;
    std::vector<float> m_colw;
    /// Runs of image columns [begin, end) between the same two lattice columns i0, i1.
    struct Span {
        int begin, end, i0, i1;
    };
    std::vector<Span> m_spans;
    std::vector<int> m_span_end;  ///< each span's end, for the lookup (backscatter_lookup.h)
    /// Each depth's slab without a log or a search per pixel (depth_slabs.h).
    std::shared_ptr<const DepthSlabs> m_slabs;
    std::shared_ptr<const BackscatterRowBounds> m_row_bounds;
};

}  // namespace deepsea
