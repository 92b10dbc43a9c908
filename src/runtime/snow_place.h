#pragma once
// Marine snow's placing as MarineSnow::draw calls it (marine_snow.cpp), and the exact integer
// conversions the placing and the drawing share.

#include <cstdint>
#include <optional>
#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/runtime/marine_snow.h"

namespace deepsea {

/// floor(x) and ceil(x) as int for |x| < 2^31, exactly: without SSE4.1 (these files are built
/// for any x86-64) std::floor is a long call, and the drawing takes four or more per particle.
inline int ifloor(float x) {
    const int i = int(x);
    return float(i) > x ? i - 1 : i;
}
inline int iceil(float x) {
    const int i = int(x);
    return float(i) < x ? i + 1 : i;
}
/// std::lround for |x| < 2^31, exactly (halves away from zero; x - i is exact): lround is a
/// libm call.
inline int iround(double x) {
    const int i = int(x);
    const double f = x - double(i);
    return f >= 0.5 ? i + 1 : (f <= -0.5 ? i - 1 : i);
}

/// Per slab of cells, the particles placed there; kept from frame to frame (their memory).
using SnowSlabs = std::vector<std::vector<SnowParticle>>;

/// snow_particles into `all` (its and the slabs' memory reused). With the frame's planar depth
/// `zdepth` (the camera's size), a particle whose centre lies behind the surface at its pixel
/// (the one nearest its image) keeps its place and id but gets diameter 0 and no draw from the
/// size spectrum (its fourth number): MarineSnow::draw draws none such, and the rest are the
/// same particles as without a depth.
void place_snow(const SnowSettings& s, const Camera& camera, std::uint64_t frame_key,
                const std::optional<CameraPose>& pose, const Image* zdepth, SnowSlabs& slabs,
                std::vector<SnowParticle>& all);

}  // namespace deepsea
