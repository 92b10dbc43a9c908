#pragma once
/// \file The baker (docs/model.md, Backscatter; docs/asset-format.md): the exact cumulative
/// single-scattering backscatter of every lattice column, from optics' backscatter_cumulative,
/// into an Asset.

#include <optional>
#include <string>

#include "deepsea/asset/asset.h"
#include "deepsea/asset/lattice.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/port.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// Version of the baker's numbers, recorded in every asset: bump it when the same inputs
/// would bake different values.
inline constexpr const char* kBakerVersion = "deepsea-bake/1";

/// Work bounds, checked before any work: a step beyond this only moves columns off the image,
/// and more depth samples than this buy no accuracy (docs/asset-format.md, "Limits").
inline constexpr int kMaxXyStep = 4096;
inline constexpr int kMaxDepthSamples = 4096;

/// Range of z_max, metres (a given one, and an automatic one is clamped to it). Below 1 cm a
/// lattice's cells shrink toward OpenVDB's smallest transform (a determinant of 3e-15 m^3:
/// z_max 1e-300 ended in "ArithmeticError: Tried to initialize an affine transform") and no
/// camera sees anything of the water; beyond 1 km even the clearest ocean water (c about
/// 0.02 / m in blue) has taken the lamps' light down by e^-40 on the way out and back, while the
/// quadrature's work grows with the path (z_max 1e6 ran on without end).
inline constexpr double kMinZMax = 0.01;
inline constexpr double kMaxZMax = 1000.0;

/// Most Monte Carlo paths per computed column, and lamp-table samples per node: 64 times the
/// defaults (HigherOrderSettings), 8 times less noise, already hours of baking on a small camera.
/// --paths 2147483647 would have run for years.
inline constexpr int kMaxPaths = 64 * 65536;
inline constexpr int kMaxLampSamples = 64 * 4096;

/// Defaults chosen by measurement (docs/asset-format.md, "Choosing the lattice").
struct BakeSettings {
    int step = 0;  ///< pixels between lattice columns, 1 .. kMaxXyStep; 0: auto (lattice_rule.h)
    int depth_samples =
        0;  ///< K slabs (K + 1 samples per column), 2 .. kMaxDepthSamples; 0: auto (64, refined)
    DepthScheme scheme = DepthScheme::Log;
    double z0 = kDefaultLogZ0;  ///< Log scheme's depth scale, metres
    double z_max = 0.0;         ///< planar depth of the last sample, metres; 0: auto
    double tolerance = 5e-4;    ///< auto z_max: the tail beyond it / the total, (0, 0.5)
    Quadrature quadrature{1e-6, 1e-14, 40};      ///< the exact integrals' accuracy
    Scattering scattering = Scattering::Single;  ///< Multiple: add orders >= 2 (Monte Carlo)
    /// Multiple only; stride 0: auto, from the field's angular detail (auto_ms_stride).
    HigherOrderSettings higher_orders = [] {
        HigherOrderSettings h;
        h.stride = 0;
        return h;
    }();
    /// Run the bake's own accuracy check (check_lattice) and record it; an automatic step or K
    /// that misses the bar is refined (up to max_refinements times) and baked again.
    bool check = true;
    int max_refinements = 3;
    /// A check that still misses the bar throws AccuracyError instead of returning the asset.
    bool strict = false;
    /// The housing's port (docs/port-bake.md, "Baking through a port"): each column is its pixel's
    /// water-side ray, recorded in the asset (BakeInfo::port). Unset: pinhole rays.
    std::optional<Port> port;
};

/// Throws ConfigError naming the setting unless the settings can be baked (step in
/// [1, kMaxXyStep] or auto, K in [2, kMaxDepthSamples] or auto, z_max in [kMinZMax, kMaxZMax]
/// or auto, paths in [1, kMaxPaths] and lamp samples in [1, kMaxLampSamples],
/// 0 < tolerance < 0.5, z0 > 0, the quadrature within its bounds, strict only with check). The
/// lattice size (kMaxLatticePoints) needs the camera: bake() checks it before each attempt.
void validate(const BakeSettings& settings);

/// The BakeInfo a bake with these inputs would record, without baking (for an auto z_max the
/// depth samples are placeholders): its input_hash equals the baked asset's, so a library can
/// skip assets that are up to date.
BakeInfo bake_request(const Camera& camera, const Rig& rig, const Water& water,
                      const BakeSettings& settings);

/// Bakes the asset of one camera x rig x water. Parallel over columns; the values are written
/// to fixed slots, so the result is bit-identical at any thread count. An automatic step or K
/// starts from lattice_rule.h's choice; with settings.check the single-scattering lattice is
/// checked (check_lattice, recorded in info.check) and, while it misses the bar, refined and
/// baked again before any Monte Carlo. Progress counts lattice columns, twice as many with an
/// auto z_max (the search visits them first); a refinement starts the count again. Throws
/// ConfigError for bad settings, a rig without lights or threads < 0, SchemaError for a port
/// the camera cannot look through (validate, check_port_view); Cancelled when the
/// progress callback returns false; AccuracyError for a strict check that misses the bar.
Asset bake(const Camera& camera, const Rig& rig, const Water& water, const BakeSettings& settings,
           const Parallel& par = {});

/// The smallest planar depth beyond which, for every column of the lattice with this step and
/// every channel, the backscatter still to come (to where exp(-2 c_min t) is negligible) is at
/// most `tolerance` of the column's total (the paper's Fig. 6 argument). Rounded up to 1 mm,
/// within [kMinZMax, kMaxZMax].
/// Progress counts lattice columns. With a port, along the columns' water-side rays.
double auto_z_max(const Camera& camera, const Rig& rig, const Water& water, int step,
                  double tolerance, const Quadrature& q = {1e-6, 1e-14, 40},
                  const Parallel& par = {}, const std::optional<Port>& port = {});

/// Path length (metres) beyond which every ray's backscatter is negligible for the auto
/// z_max search with this tolerance: exp(-2 c_min t) < 1e-4 tolerance.
double far_path_length(const Water& water, double tolerance);

}  // namespace deepsea
