#pragma once
/// \file How fine a bake's lattice must be (docs/asset-format.md, "Choosing the lattice"): the
/// xy step from the angular detail of the lamps and the camera's angular pixel size, and the
/// refinement when the bake's own check (check_lattice) measures more error than the bar.

#include "deepsea/asset/asset.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// The accuracy bar of every asset: relative error of the lookup against exact per-pixel
/// integration, mean over test pixels (worst scene) and worst test pixel.
inline constexpr double kBarMeanRel = 0.0025;
inline constexpr double kBarMaxRel = 0.01;

/// The coarsest automatic step, pixels (wide beams on fine cameras: the field is smooth and the
/// file is dominated by the preview grids).
inline constexpr int kMaxAutoStep = 16;

/// Lattice columns per angular detail of the lamps: the automatic step spans at most this
/// fraction of the narrowest lamp's detail (measured: docs/asset-format.md).
inline constexpr double kStepPerDetail = 0.06;

/// A refinement aims at this fraction of the bar, a margin for what the sample did not see.
inline constexpr double kRefineTarget = 0.7;

/// Automatic depth samples K before any refinement (docs/asset-format.md, the depth table).
inline constexpr int kDefaultDepthSamples = 64;

/// Angular scale (radians) over which a lamp's intensity profile bends: sqrt(peak / max |I''|).
/// A Gaussian gives its sigma; a table the same from its second differences at the knots. A
/// cutoff is not counted (the check sees its edge).
double profile_detail(const Rid& rid);

/// The automatic xy step: kStepPerDetail of the narrowest lamp detail, in pixels of the
/// camera's largest angular pixel size (1 / min(fx, fy) radians, at the principal point),
/// within [1, kMaxAutoStep].
int auto_step(const Camera& camera, const Rig& rig);

/// Multiple scattering's columns (docs/asset-format.md, "Multiple-scattering columns"): the
/// spacing spans this fraction of the narrowest angular detail of orders >= 2 (measured on
/// crossing pencil beams, docs/asset-format.md).
inline constexpr double kMsSpacingPerDetail = 0.25;

/// The coarsest automatic spacing, radians on the axis: the demo's (64 px at fx = 600), which
/// the Cycles and path-tracer comparisons of docs/model.md measured.
inline constexpr double kMaxMsSpacing = 0.11;

/// Monte Carlo paths an automatic stride may spend on the computed columns (400 columns at the
/// default 65536 paths: the default 800x800 asset stays within its 90 s on 2 cores). A finer
/// spacing than this allows is widened, and the check says what that costs.
inline constexpr double kMsPathBudget = 400.0 * 65536.0;

/// Angular scale (radians, seen from the camera) of the narrowest detail of orders >= 2: per
/// lamp, its profile_detail times the parallax factor (the beam's width s sigma at distance s
/// from the lamp over its distance t from the camera, least where the axis is in view and its
/// light not negligible), widened by the phase function's median scattering angle (added in
/// quadrature); the least over lamps.
double ms_detail(const Camera& camera, const Rig& rig, const Water& water);

/// The automatic multiple-scattering stride (lattice columns between computed columns, >= 1):
/// kMsSpacingPerDetail of ms_detail, at most kMaxMsSpacing, in lattice steps of the camera's
/// largest angular pixel size; widened until the computed columns times `paths` fit
/// kMsPathBudget.
int auto_ms_stride(const Camera& camera, const Rig& rig, const Water& water, int step, int paths);

/// What to change when a check missed the bar (0: leave that parameter as it is).
struct Refinement {
    int step = 0;           ///< the new xy step, or 0
    int depth_samples = 0;  ///< the new K, or 0
    bool changed() const;
};

/// The next lattice after a check that missed the bar: bilinear and linear interpolation
/// error fall as the square of the spacing, so each auto parameter whose own error (check's
/// columns_* for depth, the rest for xy) misses kRefineTarget of the bar shrinks its
/// spacing by sqrt(error / (kRefineTarget bar)), at least one step. `step_auto`/`depth_auto`: which
/// may change. K stays <= 4096.
Refinement refine(const LatticeCheck& check, int step, int depth_samples, bool step_auto,
                  bool depth_auto);

/// Whether a check meets the bar.
bool meets_bar(const LatticeCheck& check);

}  // namespace deepsea
