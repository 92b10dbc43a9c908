#pragma once
/// \file Camera-side forward scatter from transport (docs/model.md, "Forward scatter from
/// transport"): the surface-to-camera point spread of the water, all scattering orders, with
/// the true path length and absorption of every scattered path, wide angles included, by Monte
/// Carlo. Paths start at the camera along a ray (backward, by reciprocity) and end where they
/// first cross the plane perpendicular to that ray at depth d: a Lambertian surface of uniform
/// radiance L_s there sends L_s back along every path that reaches it, so the radiance seen
/// along the ray is L_s (exp(-c d) + sum over rings of share), each ring's share being what
/// reaches the surface at angles psi in the ring as seen from the camera. One set of paths
/// serves every depth: a path is scored on each plane where it first crosses it.

#include <cstdint>
#include <vector>

#include "deepsea/core/parallel.h"
#include "deepsea/core/vec.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// The point spread of one water at a few surface depths: the share of a uniform Lambertian
/// plane's radiance that reaches the camera after scattering, per ring of apparent angle psi
/// from the viewing ray, per channel, and the unscattered fraction exp(-c d). Plain data: the
/// asset stores it (docs/asset-format.md, `deepsea:forward_psf`).
struct ForwardPsfTable {
    std::vector<double> depth;      ///< plane depths along the ray, metres, ascending, > 0
    std::vector<double> ring_edge;  ///< psi ring edges, radians: 0, ..., pi/2 (rings + 1 values)
    std::vector<Rgb> share;         ///< share[k * rings() + i]: scattered share on ring i, depth k
    std::vector<Rgb> direct;        ///< direct[k] = exp(-c depth[k]), the unscattered fraction
    std::vector<Rgb> std_error;     ///< std_error[k]: standard error of depth k's total share
    int paths = 0;                  ///< Monte Carlo paths traced
    std::uint64_t seed = 0;         ///< their base seed

    int rings() const { return int(ring_edge.size()) - 1; }
    int depths() const { return int(depth.size()); }
    /// Sum of depth k's shares over every ring: the scattered light, all angles.
    Rgb total(int k) const;
    /// Throws ConfigError (naming `what`) unless the sizes agree, depths ascend from > 0, ring
    /// edges ascend from 0 to pi/2 and every value is finite and >= 0.
    void validate(const char* what) const;
};

/// Monte Carlo settings of the table.
struct ForwardTransportSettings {
    int paths = 1 << 18;     ///< paths, >= 1 (each scores every depth)
    std::uint64_t seed = 1;  ///< results depend on it, never on the threads
    int rings = 48;          ///< rings of psi: the first to 1e-4 rad, then log-spaced to pi/2
    int max_order = 1000;    ///< scatterings a path may have (1: single scattering, for checks)
};

/// `n` plane depths for surfaces out to `far` metres: far ((k + 1) / n)^2, dense near the
/// camera, where the share grows fastest.
std::vector<double> forward_psf_depths(double far, int n = 32);

/// The table by Monte Carlo. Phase functions are importance-sampled (phase_sampling.h); free
/// flights use the smallest channel's attenuation, each channel weighted by its own
/// exp(-c r) and b (as optics/multiple_scattering.h); the first scattering is drawn inside the
/// deepest plane, stratified, so that no path is spent on the unscattered light, which
/// `direct` holds exactly. Polls par.stop between blocks of paths.
ForwardPsfTable trace_forward_psf(const Water& water, const std::vector<double>& depths,
                                  const ForwardTransportSettings& settings,
                                  const Parallel& par = {});

}  // namespace deepsea
