#pragma once
/// \file Exact single-scattering backscatter along a viewing ray (docs/model.md, "Backscatter").
/// t is the path length from the camera along the unit viewing direction; the integral
/// runs in t (dt = dz / cos(phi)), never with the paper's dz * cos(phi) weight.

#include <vector>

#include "deepsea/core/parallel.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// Light of lamp L scattered at point X into the unit direction `out` (where the scattered
/// light goes): beta(psi) I_L(theta) exp(-c d1) / d1^2 per channel, 1/m times W/(m^2 sr) for
/// W/sr lamps, with d1 = |X - L|, cos(psi) = w . out, w the unit vector lamp -> X. Zero at the
/// lamp itself. Writes d1 where asked. The one home of the in-scatter equation.
Rgb lamp_in_scatter(const Light& L, const Water& water, const Vec3& X, const Vec3& out,
                    double* d1_out = nullptr);

/// Radiance added per metre of path at X = t * dir that reaches the camera:
/// sum_l beta(psi) I_l(theta') exp(-c (d1' + t)) / d1'^2, W/(m^3 sr) ... per channel.
/// dir must be a unit vector.
Rgb in_scatter(const Rig& rig, const Water& water, const Vec3& dir, double t);

/// Accuracy request for the adaptive quadrature.
struct Quadrature {
    double rel_tol = 1e-7;   ///< relative to the running integral's magnitude
    double abs_tol = 1e-14;  ///< radiance
    int max_depth = 40;      ///< bisection levels
};

/// Smallest relative tolerance accepted: below it double precision cannot converge and the
/// adaptive bisection only spends time (every level doubles the work).
inline constexpr double kMinRelTol = 1e-12;
/// Largest: above it the integral is not worth the name.
inline constexpr double kMaxRelTol = 0.1;
/// Deepest bisection accepted (the work per integral grows as 2^max_depth in the worst case).
inline constexpr int kMaxQuadratureDepth = 60;
/// Most Gauss-Kronrod panels one call of backscatter_integral or backscatter_cumulative (one
/// ray) evaluates in its depth-first bisection; a ray that runs out is integrated again by a
/// greedy pass (always the panel furthest from its tolerance) within the same number. So a
/// ray's work is bounded whatever the tolerance and depth allow (a depth of 40 allows 2^40
/// panels: on an 80-degree camera with z_max 1000 m some rays ran for more than 300 s).
/// Measured with the bake's quadrature and the authors' two lamps in Jerlov IB: the demo
/// camera's rays need 530 panels on average, at most 850 (z_max 30 m) and 9000 (1000 m), and
/// never reach the cap; an 80-degree camera's reach it beyond z_max 100 m, where the greedy pass
/// gives the unbounded integral to 1.5e-9 in at most about 0.7 s per ray.
inline constexpr long kMaxQuadraturePanels = 1L << 15;

/// ConfigError unless rel_tol is in [kMinRelTol, kMaxRelTol], abs_tol >= 0 and max_depth in
/// [1, kMaxQuadratureDepth]: every user of the quadrature checks this before it starts.
void validate(const Quadrature& q);

/// Result of one integral: value and the quadrature's own error estimate (per channel).
struct Integral {
    Rgb value;
    Rgb error;
};

/// Backscatter radiance from path t0 to t1 (metres) along unit direction dir, by adaptive
/// Gauss-Kronrod (7-15) quadrature with the stated tolerance (or down to rounding error), in at
/// most 2 kMaxQuadraturePanels panels. Polls `stop` (may be null) at every panel: Cancelled once it
/// is set.
Integral backscatter_integral(const Rig& rig, const Water& water, const Vec3& dir, double t0,
                              double t1, const Quadrature& q = {}, const StopFlag* stop = nullptr);

/// The same along the ray X(t) = origin + t dir (the water-side ray of a port, which starts on
/// its outer surface): in-scatter at X toward -dir, attenuated by exp(-c t) back to the origin.
/// origin = 0 is the overload above.
Integral backscatter_integral(const Rig& rig, const Water& water, const Vec3& origin,
                              const Vec3& dir, double t0, double t1, const Quadrature& q = {},
                              const StopFlag* stop = nullptr);

/// Cumulative backscatter B(t_k) = integral from 0 to t_k for ascending t_k >= 0 (t_0 may be 0),
/// in at most 2 kMaxQuadraturePanels panels for the whole ray; `stop` as backscatter_integral.
std::vector<Rgb> backscatter_cumulative(const Rig& rig, const Water& water, const Vec3& dir,
                                        const std::vector<double>& t, const Quadrature& q = {},
                                        const StopFlag* stop = nullptr);

/// The same along the ray X(t) = origin + t dir (a port's water-side ray, from its outer
/// surface): the baker's columns through a port. origin = 0 is the overload above.
std::vector<Rgb> backscatter_cumulative(const Rig& rig, const Water& water, const Vec3& origin,
                                        const Vec3& dir, const std::vector<double>& t,
                                        const Quadrature& q = {}, const StopFlag* stop = nullptr);

}  // namespace deepsea
