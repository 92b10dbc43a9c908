#pragma once
/// \file Marine snow's particles lit in float rows (vectorised): optics' particle_geometry,
/// gaussian_lamp_term (or lamp_term for tabulated profiles), henyey_greenstein and
/// transmission on structure-of-arrays particles, as optics' particle_radiance does one
/// particle in double (MarineSnow.FloatLightMatchesParticleRadiance compares them).

#include <vector>

#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/snow.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// n particles as rows: camera-frame centres (metres), 1 / |X| and diameters (metres).
struct ParticleRows {
    int n = 0;
    const float* x = nullptr;
    const float* y = nullptr;
    const float* z = nullptr;
    const float* inv_d2 = nullptr;
    const float* diameter = nullptr;
};

/// Scratch rows for snow_light, 5 n floats.
struct SnowLightScratch {
    float* r;
    float* g;
    float* b;
    float* theta;
    float* cos_psi;
};

/// The light each particle brings to the image, per channel (planar rows er, eg, eb): its
/// radiance toward the camera (albedo sum over lamps of the lamp term times the phase
/// function), times transmission(c, |X|), times its image's area in pixels, pi D^2 / 4 fx fy
/// |X| / z^3. Gaussian lamps and isotropic or Henyey-Greenstein phase functions are evaluated
/// in the rows; tabulated lamp profiles and Petzold phase functions per particle.
/// With a multiple-scattering asset's lamp fields (one per lamp; empty: none) each particle
/// also scatters the lamps' scattered light (optics' particle_radiance with fields).
void snow_light(const Rig& rig, const Water& water, const Snow& snow, double fx, double fy,
                const ParticleRows& p, float* er, float* eg, float* eb,
                const SnowLightScratch& scratch, const std::vector<LampField>& scattered = {});

/// SnowSizes at n quantiles in [0, 1), in place (q[i] becomes the diameter, metres), vectorised
/// (libmvec's pow, 4 ulp at most): within 1e-14 of SnowSizes relative for slopes up to 4 (the
/// presets'), 1e-12 up to 6 (SnowSizes.RowsMatchScalar). The placing's one transcendental per
/// particle.
void snow_diameters(const SnowSizes& sizes, double* q, int n);

}  // namespace deepsea
