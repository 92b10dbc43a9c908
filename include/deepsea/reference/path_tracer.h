#pragma once
/// \file The all-order reference (docs/reference.md): a plain unbiased path tracer of the scene
/// every renderer draws (the depth map's surface, the rig's point lamps, homogeneous water,
/// Lambertian albedo), with per-pixel standard errors. Slow but exact in expectation: the
/// truth the baked multiple scattering is measured against. Written apart from the baker's
/// estimator (optics/multiple_scattering.h), with other sampling, so that the two check each
/// other.

#include <cstdint>

#include "deepsea/core/image.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/layers.h"

namespace deepsea {

/// Most paths x pixels one call may trace (ConfigError beyond): about a week on two cores
/// (10^4 to 10^5 paths per second per core, turbid to clear water).
inline constexpr double kMaxPathWork = 1e10;
/// Default highest order: in water with b <= 0.98 c the orders beyond hold less than 1e-8 of
/// the light; only a conservative water (c = b) ever reaches it.
inline constexpr int kDefaultMaxOrder = 1000;

struct PathTracerOptions {
    long paths = 256;        ///< camera paths per pixel
    std::uint64_t seed = 1;  ///< path i of pixel p uses the stream mix_seed(seed, p, i)
    /// Orders counted: a path's order is its number of interactions (scatterings in the water
    /// and reflections at the surface). max_order 1 is single scattering (render_reference's
    /// direct and backscatter); min_order 2 leaves out what single scattering has.
    int min_order = 1;
    int max_order = kDefaultMaxOrder;
    /// Rays through uniform random points of the pixel's square (a box filter, as Cycles'),
    /// instead of through its centre (what the other renderers compute).
    bool box_filter = false;
    /// Open-water camera rays end at this planar depth in metres; 0: where the transmission
    /// along them is negligible (as ReferenceOptions::open_water_z). Scattered rays never end.
    double open_water_z = 0.0;
};

/// ConfigError unless paths >= 1, 1 <= min_order <= max_order, open_water_z >= 0 and paths x
/// pixels <= kMaxPathWork (the message says how many that is).
void validate(const PathTracerOptions& opt, long pixels);

/// Estimates and their standard errors.
struct PathTraced {
    /// final = direct + forward + backscatter, split by the path's first interaction as the
    /// runtime splits its layers: direct, the light reflected at the pixel's own surface point
    /// (lit by the lamps straight or through the water); forward, light that scattered in the
    /// water first but was reflected by the surface somewhere; backscatter, light that never
    /// met the surface. transmission, depth and normal are exact, as render_reference's.
    Layers layers;
    /// Per-pixel standard error of final, direct, forward and backscatter (the others empty).
    Layers std_error;
};

/// Path-traces every pixel (par.threads workers, progress per pixel, par.stop polled per path).
/// rgb: linear albedo, 3 channels; zdepth: planar depth, 1 channel; both the camera's size
/// (InputError otherwise). The surface is taken as open water or one plane (InputError for
/// other depth maps: detail::SceneSurface). Deterministic for a seed at any thread count.
PathTraced render_path_traced(const Camera& camera, const Rig& rig, const Water& water,
                              const Image& rgb, const Image& zdepth,
                              const PathTracerOptions& opt = {}, const Parallel& par = {});

}  // namespace deepsea
