#pragma once
/// \file The camera housing's port (docs/ports.md): a flat or dome window between the camera in
/// air and the water, with Refractive COLMAP's parameters (FLATPORT, DOMEPORT), so that its
/// calibrations carry over. A pixel's in-air ray from the camera centre is refracted at the
/// port's inner and outer surfaces (Snell's law, vector form); the water-side ray starts on the
/// outer surface. Pure geometry on plain structs: the one home of the port's rays for every
/// renderer and the baker.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/vec3t.h"

namespace deepsea {

/// A flat port (Refractive COLMAP's FLATPORT: Nx, Ny, Nz, int_dist, int_thick). Its inner
/// surface is the plane {x : n . x = distance} with n = normal / |normal|, the outer surface
/// the parallel plane glass_thickness further along n.
struct FlatPort {
    Vec3 normal{0.0, 0.0, 1.0};    ///< interface normal, camera frame, pointing into the water;
                                   ///< any non-zero length (normalised where used)
    double distance = 0.0;         ///< m, camera centre to the inner surface along n (int_dist)
    double glass_thickness = 0.0;  ///< m (int_thick)
};

/// A dome port (Refractive COLMAP's DOMEPORT: Cx, Cy, Cz, int_radius, int_thick): a spherical
/// shell, inner radius `radius`, outer radius radius + glass_thickness.
struct DomePort {
    Vec3 centre{0.0, 0.0, 0.0};    ///< m, the sphere's centre in the camera frame (Cx, Cy, Cz):
                                   ///< the camera centre's decentring is -centre
    double radius = 0.0;           ///< m, the inner surface's radius (int_radius)
    double glass_thickness = 0.0;  ///< m (int_thick)
};

enum class PortKind { Flat, Dome };

/// A port and the refractive indices on its three sides (COLMAP's na, ng, nw).
struct Port {
    PortKind kind = PortKind::Flat;
    FlatPort flat;          ///< used when kind is Flat
    DomePort dome;          ///< used when kind is Dome
    double n_air = 1.0;     ///< inside the housing
    double n_glass = 1.49;  ///< the window: acrylic (PMMA, 1.49 at 589 nm)
    /// The water, per channel R, G, B; equal values: no dispersion. Default: seawater, 35 PSU,
    /// about 1.34 over the visible (Quan and Fry 1995: 1.3394 at 20 C, 589 nm).
    Rgb n_water{1.34};
    /// The radiance factor (port_radiance_factor) includes the Fresnel transmittance of both
    /// surfaces; otherwise only the n^2 law.
    bool fresnel = false;

    /// The water's index differs between channels: the water-side directions do too.
    bool dispersive() const { return n_water.r != n_water.g || n_water.g != n_water.b; }
    /// "flat" or "dome": the YAML key (camera.port.<name>).
    const char* name() const { return kind == PortKind::Flat ? "flat" : "dome"; }
};

/// The keys of camera.port (docs/config.md); readers accept no others.
namespace schema {
inline const std::vector<std::string> kPort = {"flat", "dome", "fresnel"};
inline const std::vector<std::string> kFlatPort = {"normal", "distance", "glass_thickness",
                                                   "n_air",  "n_glass",  "n_water"};
inline const std::vector<std::string> kDomePort = {"centre", "radius",  "glass_thickness",
                                                   "n_air",  "n_glass", "n_water"};
}  // namespace schema

/// Largest length of a port, metres (distance, radius, glass thickness, |dome centre|): a
/// housing's window is centimetres across; 10 m keeps every square far inside double range.
inline constexpr double kMaxPortLength = 10.0;

/// Refracts unit direction d at a surface with unit normal n (either orientation) from index
/// n1 into n2: Snell's law in vector form. With m = n oriented along d, c = d . m = cos(t1)
/// and eta = n1 / n2: t = eta (d - c m) + sqrt(1 - eta^2 (1 - c^2)) m, whose part along the
/// surface is eta times d's (n1 sin t1 = n2 sin t2, in the plane of d and n). Returns false on
/// total internal reflection (eta^2 (1 - c^2) > 1), leaving t untouched.
template <class T>
inline bool refract(Vec3T<T> d, Vec3T<T> n, T n1, T n2, Vec3T<T>& t) {
    T c = dot(d, n);
    if (c < T(0)) {
        n = n * T(-1);
        c = -c;
    }
    const T eta = n1 / n2;
    const T k = T(1) - eta * eta * (T(1) - c * c);
    if (k < T(0)) return false;
    const T cos_t = std::sqrt(k);
    t = {eta * (d.x - c * n.x) + cos_t * n.x, eta * (d.y - c * n.y) + cos_t * n.y,
         eta * (d.z - c * n.z) + cos_t * n.z};
    return true;
}

/// Fresnel power transmittances of one surface from n1 into n2 for s and p polarisation, from
/// the cosines of the incident and refracted angles (1 - r^2 with the Fresnel amplitudes
/// r_s = (n1 ci - n2 ct) / (n1 ci + n2 ct), r_p = (n2 ci - n1 ct) / (n2 ci + n1 ct)). The same
/// either way through the surface (reciprocity).
template <class T>
struct FresnelT {
    T s, p;
};
template <class T>
inline FresnelT<T> fresnel_transmittance(T n1, T n2, T cos_i, T cos_t) {
    const T rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    const T rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    return {T(1) - rs * rs, T(1) - rp * rp};
}

/// Why a ray through the port has no water-side ray.
enum class PortRayStatus {
    Ok,
    Behind,           ///< a flat port's inner surface is not in front along this ray
    InnerReflection,  ///< total internal reflection at the inner surface (air to glass)
    OuterReflection,  ///< total internal reflection at the outer surface (glass to water)
};

/// One pixel's ray through the port. Points in metres, camera frame; directions unit.
struct PortRay {
    PortRayStatus status = PortRayStatus::Ok;
    Vec3 air;     ///< the in-air direction from the camera centre
    Vec3 inner;   ///< where it meets the inner surface
    Vec3 glass;   ///< the direction inside the glass
    Vec3 origin;  ///< where it leaves the outer surface: the water-side ray's origin
    /// The water-side direction per channel R, G, B (all three equal without dispersion).
    std::array<Vec3, 3> direction{};
    /// Cosines to the surface normals (for Fresnel): the in-air ray and the glass ray at the
    /// inner surface, the glass ray and the water ray (per channel) at the outer surface.
    double cos_air = 1.0, cos_glass_inner = 1.0, cos_glass_outer = 1.0;
    Rgb cos_water{1.0};

    /// A water-side ray exists in every channel.
    bool valid() const { return status == PortRayStatus::Ok; }
};

/// The ray with in-air direction `air` (any non-zero length) from the camera centre, traced
/// through the port. Where it fails (status), the fields up to the failing surface are set.
PortRay trace_port(const Port& port, const Vec3& air);

/// The ray of image point (u, v): trace_port of the pinhole ray Camera::ray(u, v).
PortRay trace_port(const Port& port, const Camera& camera, double u, double v);

/// Factor from water-side radiance to the in-air radiance reaching the camera along a traced
/// ray, per channel: (n_air / n_water)^2, the n^2 law (L / n^2 is invariant along a ray across
/// lossless interfaces; the glass's index cancels), times, with port.fresnel, the unpolarised
/// Fresnel transmittance of both surfaces, (Ts1 Ts2 + Tp1 Tp2) / 2 (each polarisation carried
/// through both surfaces; reflections inside the glass left out). 0 for an invalid ray.
Rgb port_radiance_factor(const Port& port, const PortRay& ray);

/// Pixels per radian of the water-side rays at the image centre, along x: fx times the ratio of
/// the in-air to the water-side angle between the (green) rays of image points (cx -+ 0.5, cy).
/// fx for a centred dome (to rounding), about n_water / n_air times fx behind a flat port; fx
/// where either ray fails. The forward blur's angular scale through the port (runtime, reference).
double port_water_fx(const Port& port, const Camera& camera);

/// Ranges of the port alone (docs/config.md): normal finite and non-zero, distance in
/// [0, kMaxPortLength], radius and glass thickness in (0, kMaxPortLength], dome centre finite
/// and inside the inner surface (|centre| < radius: the camera inside the dome), indices > 0
/// and finite. Throws SchemaError naming the key (camera.port.flat.glass_thickness, ...).
void validate(const Port& port);

/// The port over a camera's image, after validate(port): every ray through the image's outer pixel
/// edges (its four corners and every pixel edge along its four sides) and its centre must reach the
/// water: SchemaError on the flat port's normal if the interface is behind the camera for one of
/// them, on n_glass or n_water if one is totally reflected (at the inner or the outer surface). A
/// flat port's worst ray is at a corner (its angle to the normal is largest at a vertex of the
/// image rectangle); a dome's is checked along the edges.
void check_port_view(const Port& port, const Camera& camera);

/// The two ports refract every ray alike: the same kind, geometry and indices (all the bake
/// and the rendered rays depend on). `fresnel` is left out: it changes only the camera stage's
/// radiance factor, not a ray.
bool same_rays(const Port& a, const Port& b);

/// One line for messages and `deepsea info`: "flat port (normal [0, 0, 1], distance 0.03 m,
/// glass 0.012 m, n_air 1, n_glass 1.49, n_water 1.34)", the dome's with centre and radius;
/// ", fresnel" where it is on.
std::string describe(const Port& port);

/// Refractive COLMAP's parameter list for the port: FLATPORT "Nx, Ny, Nz, int_dist, int_thick,
/// na, ng, nw" or DOMEPORT "Cx, Cy, Cz, int_radius, int_thick, na, ng, nw" (the normal written
/// unit, as COLMAP requires; nw the green channel's index).
std::vector<double> colmap_params(const Port& port);
/// The port of a Refractive COLMAP model name ("FLATPORT", "DOMEPORT") and its 8 parameters;
/// ConfigError for another name or count. Not validated.
Port port_from_colmap(const std::string& model, const std::vector<double>& params);

}  // namespace deepsea
