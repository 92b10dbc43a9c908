#pragma once
/// \file All-order light transport in homogeneous water by Monte Carlo (docs/model.md,
/// "Multiple scattering"). Single scattering stays exact (backscatter.h); these estimators add
/// the light that scattered two or more times, so their noise touches only that part.
///
/// Method: backward paths from the viewer; every path segment connects to every lamp by
/// equiangular sampling (Kulla & Fajardo 2012), which cancels the 1/d^2 of a point lamp, so
/// the estimate stays finite next to the lamps; free flights are sampled with the smallest
/// channel's attenuation and carry per-channel weights; Russian roulette, after each segment's
/// next event, ends paths without bias. Deterministic: results depend only on the seeds.

#include <cstdint>
#include <utility>
#include <vector>

#include "deepsea/core/parallel.h"
#include "deepsea/core/random.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/phase_sampling.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// Monte Carlo settings.
struct MonteCarlo {
    int paths = 4096;        ///< paths per ray
    std::uint64_t seed = 1;  ///< base seed; each ray has its own stream
    /// higher_orders_cumulative: the value at each depth sample but the last is the water light
    /// in front of an absorbing wall there (the plane z = that sample's planar depth), not in
    /// water without walls (docs/model.md, "Water light in front of a surface").
    bool wall = false;
    /// Per channel, > 0: Estimate::tail gets the part of each path's light above this (the
    /// path's total to the last sample; each of its samples in the same proportion).
    Rgb tail_above{};
    /// With tail_above: the threshold is at least this many times the estimate's own mean at
    /// the last sample (known after all paths; those above it are traced again for the split).
    double tail_of_mean = 0.0;
};

/// The water and lamps, with what every path needs precomputed.
class Transport {
public:
    Transport(const Rig& rig, const Water& water);

    /// One-sample estimate of the radiance arriving at X from the unit direction d (light
    /// travelling along -d) that has scattered at least once: the unscattered lamp light, which
    /// the analytic terms give exactly, is left out. W/(m^2 sr) for lamps in W/sr.
    Rgb scattered_radiance(Vec3 X, Vec3 d, Rng& rng) const;
    /// The same path's contributions, appended to `out` as (z, light) with z the largest
    /// camera-frame z the path reached before the light joined it (X's included): in front of
    /// an absorbing wall z = Z (lamps in front of it) that light is there exactly when z <= Z.
    void scattered_contributions(Vec3 X, Vec3 d, Rng& rng,
                                 std::vector<std::pair<double, Rgb>>& out) const;

    /// The next backward direction at a scattering vertex X reached along the backward
    /// direction `from`, with weight p(from . d) / pdf(d). pdf mixes the phase function about
    /// `from` with, for each lamp, the phase function about the direction from X toward it and
    /// a cone uniform in the angle to it: the light that reaches X after scattering forward on
    /// the next segment comes from there, a forward-peaked phase function (g = 0.9) makes it a
    /// sharp spike that the first strategy alone samples badly, and the lamp's glow grows as
    /// 1 / angle (one-sample MIS, balance heuristic).
    PhaseSample next_direction(const Vec3& X, const Vec3& from, Rng& rng) const;
    /// Density of next_direction's choice of d, 1/sr; `from` may be null: then the mixture's
    /// first half is uniform over the sphere instead of the phase function.
    double direction_pdf(const Vec3& X, const Vec3* from, const Vec3& d) const;
    /// Samples d from that mixture with a uniform first half (for estimators of the radiance
    /// arriving at X from all directions); weight 1 / pdf.
    PhaseSample any_direction(const Vec3& X, Rng& rng) const;

    const Rig& rig() const { return m_rig; }
    const Water& water() const { return m_water; }
    const PhaseSampler& sampler() const { return m_sampler; }
    /// Path length beyond which a path's light is below 1e-6 of what it had (metres).
    double far() const { return m_far; }

private:
    /// A direction from the mixture that direction_pdf describes.
    Vec3 sample_mixture(const Vec3& X, const Vec3* from, Rng& rng) const;
    /// Light scattered once on the ray X + r d (r > 0) toward -d, from lamp L, one equiangular
    /// sample: integral of exp(-c r) beta I_L exp(-c d1) / d1^2 dr.
    /// `z_at` (may be null) receives the camera-frame z of the point the sample scattered at.
    Rgb segment_from_lamp(const Light& L, const Vec3& X, const Vec3& d, double u,
                          double* z_at = nullptr) const;

    Rig m_rig;
    Water m_water;
    PhaseSampler m_sampler;
    double m_c_min = 0.0;  ///< the smallest channel's attenuation: free flights use it
    double m_far = 0.0;
    double m_theta_p = M_PI;  ///< median scattering angle of the phase function, radians
};

/// Per-sample value of a Monte Carlo estimate and its standard error.
struct Estimate {
    std::vector<Rgb> value;
    std::vector<Rgb> std_error;
    /// With MonteCarlo::tail_above: the share of `value` from the paths' light above it, per
    /// sample (empty otherwise). value - tail is what the paths gave below it.
    std::vector<Rgb> tail;
};

/// Radiance reaching the viewer at the origin along unit direction dir from light that
/// scattered two or more times, collected from path length 0 to t[k] (t ascending, t[0] >= 0):
/// add backscatter_cumulative for all orders. With mc.wall, every sample but the last is that
/// light in front of an absorbing wall at the sample's planar depth (paths that reach beyond it
/// add nothing there); the last stays water without walls (open water). `stream` picks the
/// ray's random stream.
/// Polls `stop` (may be null) before every path: Cancelled once it is set.
Estimate higher_orders_cumulative(const Transport& transport, const Vec3& dir,
                                  const std::vector<double>& t, const MonteCarlo& mc,
                                  std::uint64_t stream, const StopFlag* stop = nullptr);
/// The same along X(s) = origin + s dir (a port's water-side ray, from its outer surface): the
/// light attenuated back to the origin. origin = 0 is the overload above.
Estimate higher_orders_cumulative(const Transport& transport, const Vec3& origin, const Vec3& dir,
                                  const std::vector<double>& t, const MonteCarlo& mc,
                                  std::uint64_t stream, const StopFlag* stop = nullptr);

}  // namespace deepsea

namespace deepsea {

/// SH coefficients (kShCount per channel, [3 * m + c]) of the scattered radiance arriving at X
/// from all directions (Transport::scattered_radiance), from `samples` directions drawn by
/// Transport::any_direction; std_error (same layout) is each coefficient's standard error.
/// The irradiance onto a Lambertian surface follows with sh_irradiance.
struct ShEstimate {
    double value[27] = {};
    double std_error[27] = {};
};
/// Polls `stop` (may be null) before every sample: Cancelled once it is set.
ShEstimate scattered_radiance_sh(const Transport& transport, const Vec3& X, int samples, Rng& rng,
                                 const StopFlag* stop = nullptr);

}  // namespace deepsea
