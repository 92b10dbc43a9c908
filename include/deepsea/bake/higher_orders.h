#pragma once
/// \file Multiple scattering in a baked asset: the light scattered two or more times, added to
/// the exact single-scattering columns (docs/model.md, "Multiple scattering").

#include "deepsea/asset/asset.h"
#include "deepsea/core/parallel.h"

namespace deepsea {

/// Bakes the scattered light around each lamp of the asset's rig (lamp_fields) with
/// asset.info.higher_orders' lamp_samples and seed, out to the frustum's far corners, and
/// records its standard error. Lamps with the same intensity profile share one table.
void add_lamp_fields(Asset& asset, const Parallel& par = {});

/// Bakes the camera-side forward scatter from transport (optics/forward_transport.h) into
/// asset.forward_psf, with asset.info.higher_orders' seed, on plane depths out to the range of
/// the frustum's far corners: only where the water's forward scatter is the phase function's
/// (`forward_scatter: on`); otherwise it leaves the asset as it is.
void add_forward_psf(Asset& asset, const Parallel& par = {});

/// Tail pooling (docs/ms-columns.md): a path's light above this many times its column's single
/// scattering (per channel, at z_max) is shared among the computed columns within
/// ms_tail_radius of it (tent weights).
inline constexpr double kMsTailAbove = 16.0;
/// ... and above this many times the column's own orders >= 2 (MonteCarlo::tail_of_mean):
/// where single scattering is negligible (dark water beside a beam) a path is a rare bright
/// one only if it is bright for that column.
inline constexpr double kMsTailOfMean = 16.0;
/// At most this many computed columns either side, and within kMsTailPerDetail of the light's
/// angular detail (lattice_rule.h, ms_detail): pooling wider blurs the beams' edges (measured
/// on crossing pencil beams, docs/ms-columns.md).
inline constexpr int kMsTailRadius = 2;
inline constexpr double kMsTailPerDetail = 0.6;

/// Computed columns within which tails are pooled, for columns `spacing` radians apart and
/// light of angular detail `detail` radians (0 where the columns are too far apart to pool).
int ms_tail_radius(double spacing, double detail);

/// Columns the Monte Carlo computes on an ni x nj lattice with this stride.
long higher_order_columns(int ni, int nj, int stride);

/// Adds the radiance of orders >= 2 to an asset holding exact single scattering (values as
/// bake() leaves them), with asset.info.higher_orders' settings, and records there what the
/// estimate measured of itself (rel_std_error, fraction) and Scattering::Multiple. Parallel
/// over computed columns; the result is identical at any thread count. Throws ConfigError for
/// paths < 1 or stride < 1, Cancelled if par.progress says stop.
void add_higher_orders(Asset& asset, const Parallel& par = {});

}  // namespace deepsea
