#pragma once
/// \file Marine snow drawn into a frame (docs/snow-shadows.md, "Marine snow"): particles placed in
/// the view up to the frame's surfaces, lit by the rig's lamps (optics/snow.h), drawn as discs of
/// their projected size widened by the lens's circle of confusion.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/camera_motion.h"
#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/snow.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// The largest disc radius drawn, pixels: a nearer, more defocused particle is drawn at this
/// radius (its light kept), so that a frame's work stays bounded.
inline constexpr double kMaxSnowRadiusPx = 32.0;

/// The longest motion streak drawn, pixels: a longer one is shortened to this about its middle
/// (its light kept), so that a frame's work stays bounded. A streak shorter than
/// kMinSnowStreakPx is drawn as the still disc.
inline constexpr double kMaxSnowStreakPx = 64.0;
inline constexpr double kMinSnowStreakPx = 1.0;

/// How marine snow is drawn: which snow, the random numbers' seed and the lens (its focal
/// length in pixels is the frame camera's fx).
struct SnowSettings {
    Snow snow;
    std::uint64_t seed = 1;
    double f_number = 2.8;
    double pixel_pitch_um = 3.45;
    double focus_distance_m = kDefaultFocusDistance;
    /// Motion streaks (docs/snow-shadows.md, "Motion streaks"): each disc swept along its
    /// image motion while the shutter is open; drawn only for frames given a pose and a
    /// shutter (MarineSnow::set_frame).
    bool streaks = false;
    /// The shutter's open time, seconds (the camera stage's exposure time, else the snow's
    /// exposure_time_ms), > 0; how the batch room finds each frame's shutter.
    double exposure_time_s = 0.01;
    /// Frames per second where the poses' timestamps give no frame interval (0: none given).
    double frame_rate_hz = 0.0;
};

/// Checks the snow and the lens values; SchemaError naming the key (snow.*,
/// camera.lens.focus_distance_m, ...).
void validate(const SnowSettings& s);

/// One particle in a frame: camera-frame centre (metres), diameter (metres), its instance id.
struct SnowParticle {
    Vec3 position;
    double diameter = 0.0;
    std::uint32_t id = 0;
};

/// The particles in the view of `camera` between kSnowNearM and the snow's max_distance_m
/// (planar depth), before surfaces hide any. Space is cut into cubic cells keyed by their
/// integer coordinates; a cell holds Poisson(concentration x volume) particles, each placed and
/// sized by numbers keyed by (seed, cell, index): with a pose, the cells are the world's
/// (particles fixed in the world, any frame made alone); without one, the camera's, with the
/// frame key in the key (drawn afresh per frame). Ids are 1, 2, ... in a fixed order.
std::vector<SnowParticle> snow_particles(const SnowSettings& s, const Camera& camera,
                                         std::uint64_t frame_key,
                                         const std::optional<CameraPose>& pose);

/// Radius (pixels) of the disc drawn for a particle of diameter D at camera-frame X: its
/// projected radius plus half the circle of confusion, at least 0.5 (a pixel), at most
/// kMaxSnowRadiusPx. (Inline: every particle drawn takes one.)
inline double snow_disc_radius_px(const Camera& camera, const ThinLens& lens, const Vec3& X,
                                  double D) {
    const double z = X.z, d2 = length(X);
    // A sphere's image: pi (D/2)^2 fx fy d2 / z^3 pixels (its solid angle over a pixel's).
    const double area = M_PI * 0.25 * D * D * camera.fx * camera.fy * d2 / (z * z * z);
    const double radius = std::sqrt(area / M_PI) + 0.5 * circle_of_confusion_px(lens, z);
    return std::clamp(radius, 0.5, kMaxSnowRadiusPx);
}

/// MarineSnow::draw's buffers (marine_snow_draw.cpp).
struct SnowScratch;

/// Keeps MarineSnow::draw's buffers from frame to frame (made on first use); a copy starts
/// without any (they hold no state between frames).
class SnowScratchHolder {
public:
    SnowScratchHolder();
    SnowScratchHolder(const SnowScratchHolder&);
    SnowScratchHolder& operator=(const SnowScratchHolder&) { return *this; }
    ~SnowScratchHolder();
    SnowScratch& get() const;

private:
    mutable std::unique_ptr<SnowScratch> m_p;
};

/// Draws marine snow into frames of one rig and water.
class MarineSnow {
public:
    /// With a multiple-scattering asset's lamp fields (one per lamp, Asset::lamp_fields) the
    /// particles also scatter the lamps' scattered light; without, only the lamps' own.
    MarineSnow(SnowSettings settings, const Rig& rig, const Water& water,
               std::vector<LampField> scattered = {});

    /// The next frame's key and, where known, its camera pose (camera to world) and its
    /// shutter's poses: with streaks on, a pose and a shutter, each particle is drawn swept
    /// from where it is seen when the shutter opens to where it is seen when it closes.
    void set_frame(std::uint64_t frame_key, std::optional<CameraPose> pose,
                   std::optional<Shutter> shutter = {});

    /// Adds the snow seen by `camera` in front of the planar depth map `zdepth` to `final`
    /// (RGB radiance); where `snow` and `ids` are given (same size, zeroed by the caller), the
    /// snow's radiance and, per pixel, the id of the particle that adds most there (0: none).
    /// A particle whose centre lies behind the surface at its pixel is not drawn; a disc's
    /// pixels behind their surface get nothing.
    void draw(const Camera& camera, const Image& zdepth, Image& final, Image* snow,
              Image* ids) const;

    /// Particles drawn in the last frame.
    int drawn() const { return m_drawn; }
    const SnowSettings& settings() const { return m_settings; }

private:
    SnowSettings m_settings;
    Rig m_rig;
    Water m_water;
    std::vector<LampField> m_scattered;
    std::uint64_t m_key = 0;
    std::optional<CameraPose> m_pose;
    std::optional<Shutter> m_shutter;
    SnowScratchHolder m_scratch;
    mutable int m_drawn = 0;
};

}  // namespace deepsea
