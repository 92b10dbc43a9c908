#pragma once
/// \file The bake's own check of orders >= 2 (docs/asset-format.md, "Multiple-scattering
/// columns"): the Monte Carlo columns interpolated as the runtime does, against a direct
/// estimate (the same estimator, twice the paths, streams of its own) along pixels' own rays
/// midway between computed columns and where the lamps' axes cross the view.

#include <cstddef>
#include <utility>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/core/parallel.h"

namespace deepsea {

/// Orders >= 2 on the computed lattice columns: every stride-th column and row and the last.
struct MsColumns {
    std::vector<int> ci, cj;  ///< lattice indices computed along u and v, ascending
    std::size_t nk = 0;       ///< depth samples per column
    std::vector<Rgb> values;  ///< column (a, b), sample k at [(a * cj.size() + b) * nk + k]
    /// Bilinear in the logarithm (a geometric mean) per channel where the four columns are
    /// positive: light that falls off exponentially away from a beam is not lifted between
    /// columns as a linear mean lifts it; plain bilinear where one is 0.
    bool log = false;

    /// Bilinear (or with `log`, log-bilinear) between computed columns at lattice coordinates
    /// (x, y) = (u, v) / step: on lattice columns what the bake stores, and in between what
    /// the runtime's bilinear lookup of those gives (each lattice cell lies within one
    /// computed cell).
    Rgb at(double x, double y, std::size_t k) const;
};

/// Lattice indices computed along an axis of n nodes: 0, stride, 2 stride, ..., and n - 1.
std::vector<int> computed_indices(int n, int stride);

/// Test columns of about this many computed cells, at their centres, are checked, plus the
/// cells where each lamp's axis is in view.
inline constexpr long kMsCheckCells = 24;

/// Paths of each direct estimate, per path of the bake's columns.
inline constexpr int kMsCheckPathFactor = 2;

/// Checks `ms` against direct estimates for the asset's camera, rig, water and port with
/// asset.info.higher_orders' paths and seed. `asset` holds exact single scattering only (the
/// total's other part). A column's error is the largest over channels and the depth samples
/// nearest 2, 4, 8 m and z_max of |interpolated - direct| / (single + direct). Deterministic at
/// any thread count; Cancelled if par.stop is set.
HigherOrderCheck check_higher_orders(const Asset& asset, const MsColumns& ms,
                                     const Parallel& par = {});

/// The test pixels check_higher_orders uses (u, v in pixels, midway between computed columns:
/// half pixels where the stride is odd), for tests and docs.
std::vector<std::pair<double, double>> ms_check_pixels(const Asset& asset, const MsColumns& ms);

}  // namespace deepsea
