#pragma once
// Marine snow's placing as MarineSnow::draw calls it (marine_snow.cpp), and the exact integer
// conversions the placing and the drawing share.

#include <cstdint>
#include <optional>
#include <unordered_map>
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

/// A cell's particles as its random numbers make them: world position (metres) and the
/// size spectrum's quantile (the stream's fourth number).
struct CellParticle {
    double x, y, z, q;
};

/// A cell's integer coordinates.
struct CellKey {
    long long i, j, k;
    bool operator==(const CellKey& o) const { return i == o.i && j == o.j && k == o.k; }
};
struct CellKeyHash {
    std::size_t operator()(const CellKey& c) const {
        return std::size_t(std::uint64_t(c.i) * 0x9e3779b97f4a7c15ull ^
                           std::uint64_t(c.j) * 0xc2b2ae3d27d4eb4full ^
                           std::uint64_t(c.k) * 0x165667b19e3779f9ull);
    }
};

/// place_snow's memory, kept from frame to frame: per slab of cells the particles placed there,
/// and, with a camera pose (cells fixed in the world), each cell's particles as generated,
/// kept while the view meets the cell (so that a flight's frames draw the random numbers of
/// the cells entering the view only: the same numbers, so the same particles, bit for bit).
struct SnowPlacing {
    std::vector<std::vector<SnowParticle>> slabs;
    /// The cells' key (seed and stream) and edge the kept cells were made with.
    std::uint64_t base = 0;
    double cell = 0.0;
    std::unordered_map<CellKey, std::uint32_t, CellKeyHash> index;  ///< cell -> slot
    std::vector<std::vector<CellParticle>> slots;
    std::vector<std::uint32_t> last_used;  ///< per slot: the frame (count) it was last met in
    std::vector<std::uint32_t> free;       ///< slots no cell holds
    std::uint32_t frame = 0;
    /// per slab: the cells met there that were not kept (generated this frame) and, for
    /// those to be kept, their keys
    std::vector<std::vector<std::vector<CellParticle>>> fresh;
    std::vector<std::vector<CellKey>> fresh_keys;
};

/// snow_particles into `all` (its and `placing`'s memory reused). With the frame's planar depth
/// `zdepth` (the camera's size), a particle whose centre lies behind the surface at its pixel
/// (the one nearest its image) keeps its place and id but gets diameter 0 and no draw from the
/// size spectrum (its fourth number): MarineSnow::draw draws none such, and the rest are the
/// same particles as without a depth.
void place_snow(const SnowSettings& s, const Camera& camera, std::uint64_t frame_key,
                const std::optional<CameraPose>& pose, const Image* zdepth, SnowPlacing& placing,
                std::vector<SnowParticle>& all);

}  // namespace deepsea
