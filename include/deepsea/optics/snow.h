#pragma once
/// \file Marine snow (docs/snow-shadows.md, "Marine snow"): the particles' size spectrum and number
/// concentration, the presets, how a particle lit by the rig's lamps looks from the camera, and
/// the thin-lens circle of confusion that blurs it. Pure functions on plain structs; the
/// runtime's MarineSnow (runtime/marine_snow.h) places and draws the particles.

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/phase.h"
#include "deepsea/optics/vec3t.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// A water's marine snow: particles of diameter D in [d_min, d_max] with the number spectrum
/// n(D) proportional to D^-slope (a truncated power law, as UVP and camera profiles report
/// it), `concentration` particles per cubic metre in that range, each scattering a fraction
/// `albedo` of the light its geometric cross-section pi D^2 / 4 intercepts with the phase
/// function `phase`.
struct Snow {
    std::string name;            ///< the preset's name, or "custom"
    double concentration = 0.0;  ///< particles per m^3 with D in [d_min, d_max], > 0
    double d_min_mm = 0.5;       ///< smallest diameter drawn, mm, > 0
    double d_max_mm = 5.0;       ///< largest, mm, > d_min_mm
    double slope = 3.5;          ///< b of n(D) ~ D^-b, in [0, 6]
    double albedo = 0.5;         ///< fraction of the intercepted light scattered, in (0, 1]
    Phase phase;                 ///< of the scattered light (isotropic by default)
    /// Particles are placed up to this planar depth (metres, > 0.1) or the scene's surface,
    /// whichever is nearer: beyond it a particle is a small part of the water's own scattering
    /// (the backscatter layer), which already holds it.
    double max_distance_m = 4.0;
    /// How the snow is drawn rather than what it is (docs/snow-shadows.md, "Motion streaks"):
    /// each particle swept along its image motion while the shutter is open, where the frames
    /// have camera poses. Off by default.
    bool streaks = false;
    /// The shutter's open time for the streaks, milliseconds, in (0, 10000]; a camera stage's
    /// own exposure time replaces it.
    double exposure_time_ms = 10.0;
    /// Frames per second, (0, 10000], for the streaks' frame interval where the poses'
    /// timestamps do not increase; 0: not given.
    double frame_rate_hz = 0.0;
};

/// The default distance a camera's lens is focused at (metres, camera.lens.focus_distance_m):
/// about where a survey camera sees the seafloor.
inline constexpr double kDefaultFocusDistance = 2.0;

/// The closest planar depth a particle is placed at, metres: the housing's port.
inline constexpr double kSnowNearM = 0.1;

/// The presets' names: "abyssal" (clear abyssal water), "nepheloid" (a bottom nepheloid
/// layer), "plume" (a sediment plume, e.g. behind a collector or a landing), docs/model.md.
const std::vector<std::string>& snow_preset_names();

/// A preset by name; ConfigError naming `key` ("--snow", "snow") and listing the presets for
/// an unknown one.
Snow snow_preset(const std::string& name, const std::string& key = "--snow");

/// Checks every value's range; SchemaError naming "snow.<key>".
void validate(const Snow& snow);

/// Diameter (metres) at the quantile q in [0, 1) of the truncated power law: the inverse of
/// its cumulative distribution (slope 1: logarithmic).
double snow_diameter(const Snow& snow, double q);

/// snow_diameter with its constants computed once: one pow per diameter.
class SnowSizes {
public:
    explicit SnowSizes(const Snow& snow);
    double operator()(double q) const;

    /// The form's constants, for a vectorised copy (runtime's snow_diameters): D = (ak + q (bk
    /// - ak))^(1 / k) with a = d_min, b = d_max (metres), k = 1 - slope, ak = a^k, bk = b^k;
    /// where |k| < 1e-9, D = a (b / a)^q.
    double a() const { return m_a; }
    double b() const { return m_b; }
    double k() const { return m_k; }
    double ak() const { return m_ak; }
    double bk() const { return m_bk; }

private:
    double m_a, m_b, m_k, m_ak, m_bk;
};

/// Volume (m^3) of the pinhole camera's view between planar depths z0 and z1 over the image's
/// pixels (u in [-0.5, width - 0.5], v likewise): (W / fx) (H / fy) (z1^3 - z0^3) / 3.
double view_volume(const Camera& camera, double z0, double z1);

/// Volume of the view in front of a depth map (planar z, metres; <= 0 or not finite: open
/// water), from z_near to min(depth, z_far) per pixel: each pixel's pyramid, (z^3 - z0^3) /
/// (3 fx fy).
double visible_volume(const Camera& camera, const std::vector<float>& zdepth, double z_near,
                      double z_far);

/// The lens for defocus: the camera's focal length in pixels (fx), the pixel pitch, the
/// f-number and the distance the lens is focused at (planar, metres, in water as seen).
struct ThinLens {
    double fx = 600.0;             ///< pixels
    double pixel_pitch_um = 3.45;  ///< metres per pixel on the sensor, in micrometres
    double f_number = 2.8;         ///< N
    double focus_distance_m = kDefaultFocusDistance;  ///< s, > focal length

    double focal_length_m() const { return fx * pixel_pitch_um * 1e-6; }
};

/// Diameter in pixels of the thin lens's circle of confusion for a point at distance z
/// (metres): c = A |z - s| / z * f / (s - f) on the sensor, A = f / N the aperture, divided
/// by the pixel pitch. Zero at z = s. (Inline: marine snow sizes every particle's disc with it.)
inline double circle_of_confusion_px(const ThinLens& lens, double z) {
    const double f = lens.focal_length_m(), s = lens.focus_distance_m;
    const double aperture = f / lens.f_number;
    const double c = aperture * std::fabs(z - s) / z * f / (s - f);
    return c / (lens.pixel_pitch_um * 1e-6);
}

/// How a lamp lights a small sphere and turns toward the camera (particle_geometry's result).
template <class T>
struct ParticleGeometry {
    T d1;         ///< lamp to particle, metres
    T cos_theta;  ///< cosine of theta, the angle between the lamp's axis and lamp -> X
    T cos_psi;    ///< cosine of the scattering angle: lamp -> X against X -> camera
};

/// Geometry of a lamp at `lamp` with unit axis `axis` lighting a particle at X (camera frame,
/// metres), inv_d2 = 1 / |X|. Templated for the runtime's float rows (lamp.h's reasons); the
/// double functions below call it too.
template <class T>
inline ParticleGeometry<T> particle_geometry(Vec3T<T> X, T inv_d2, Vec3T<T> lamp, Vec3T<T> axis) {
    using std::sqrt;
    const Vec3T<T> lx = X - lamp;
    const T d1 = sqrt(dot(lx, lx));
    const T inv = T(1) / d1;
    return {d1, dot(axis, lx) * inv, -dot(lx, X) * (inv * inv_d2)};
}

/// Irradiance (W/m^2 per channel) of lamp L on a small sphere at X (camera frame, metres): the
/// lamp term I0 RID(theta) exp(-c d1) / d1^2 with no Lambert cosine (optics/lamp.h's
/// lamp_term with lamp_spread(d1, 1)). Writes the unit vector lamp -> X to w.
Rgb lamp_irradiance_at(const Light& L, const Water& water, const Vec3& X, Vec3* w = nullptr);

/// Radiance (W/(m^2 sr) per channel) a particle at X sends toward the camera, before the water
/// between them: albedo sum_l E_l p(psi_l), with E_l lamp_irradiance_at and psi_l the angle
/// between lamp -> X and X -> camera. Its image, pi D^2 / 4 of projected area, carries this
/// radiance times transmission(c, |X|).
Rgb particle_radiance(const Rig& rig, const Water& water, const Snow& snow, const Vec3& X);

/// particle_radiance plus the lamps' scattered light where a multiple-scattering asset's lamp
/// fields are given (one per lamp, Asset::lamp_fields; an empty field adds nothing): albedo
/// sum_l I_l quadratic_in_scatter of lamp l's field at X, seen along X / |X|, with the snow's
/// phase function's Legendre moments. The field holds the light scattered in water that ends
/// nowhere (no surface behind the particle), like the surfaces' scattered light.
Rgb particle_radiance(const Rig& rig, const Water& water, const Snow& snow, const Vec3& X,
                      const std::vector<LampField>& scattered);

/// A camera's pose in a world frame: its centre and the world directions of its axes (OpenCV:
/// x right, y down, z forward).
struct CameraPose {
    Vec3 origin;
    Vec3 right{1, 0, 0};
    Vec3 down{0, 1, 0};
    Vec3 forward{0, 0, 1};
};

}  // namespace deepsea
