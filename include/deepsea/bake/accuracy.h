#pragma once
/// \file How well an asset's lookup (Asset::sample, the runtime's interpolation) reproduces
/// exact per-pixel integration (backscatter_cumulative along each pixel's own ray: through the
/// asset's port, its water-side ray from the port's outer surface, bake_ray.h). This is
/// what `deepsea bake --check` prints and what docs/asset-format.md tabulates.

#include <string>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/backscatter.h"

namespace deepsea {

struct AccuracyOptions {
    std::vector<double> plane_depths{2.0, 4.0, 8.0};  ///< planar depths of test planes, metres
    /// Also rows for open water: the lookup at z_max vs the exact integral to z_max
    /// (interpolation only), and vs the integral to the far path length (what truncating
    /// at z_max costs on top).
    bool open_water = true;
    /// Test pixels: every stride-th pixel in u and v from stride / 2, plus the last row and
    /// column. An odd stride puts most test pixels between lattice columns.
    int stride = 7;
    /// Explicit test pixel columns and rows (their product is tested); empty: the stride grid.
    std::vector<int> us, vs;
    Quadrature quadrature{1e-9, 1e-16, 40};  ///< for the exact reference
};

/// Errors of one scene over the test pixels. A pixel's error is the largest relative error
/// of its three channels, |lookup - exact| / exact.
struct AccuracyRow {
    std::string scene;         ///< "plane 2 m", "open water (z_max)", "open water (inf)"
    double z = 0.0;            ///< planar depth looked up, metres
    double mean_rel = 0.0;     ///< mean over test pixels
    double max_rel = 0.0;      ///< worst test pixel
    int max_u = 0, max_v = 0;  ///< where the worst pixel is
    long pixels = 0;
};

/// Compares the asset's lookup with exact integration for its own camera, rig and water.
/// Deterministic at any thread count. Progress counts rows of test pixels.
std::vector<AccuracyRow> evaluate_asset_accuracy(const Asset& asset,
                                                 const AccuracyOptions& opt = {},
                                                 const Parallel& par = {});

/// Test pixels of the bake's own check: about this many lattice cells are tried at their
/// centre (where bilinear interpolation errs most), plus a quarter as many lattice columns.
inline constexpr long kCheckCells = 128;

/// The bake's own check (docs/asset-format.md, "The bake's check"): evaluate_asset_accuracy on
/// a sample of pixels, the centres of every m-th lattice cell in u and v (m chosen for about
/// kCheckCells cells) and every 2m-th lattice column, all scenes, the asset's quadrature (rel_tol
/// at most 1e-6). Costs
/// about as many exact integrals as kCheckCells * 1.25 lattice columns. Returns the worst
/// scene's mean and the worst pixel, over all test pixels and over the column pixels alone.
LatticeCheck check_lattice(const Asset& asset, const Parallel& par = {});

}  // namespace deepsea
