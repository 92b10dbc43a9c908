#pragma once
/// \file The camera / rig / water schema in one place: the keys of each section and the range
/// of every value. The YAML configs (io/config.cpp) and the asset's `deepsea:bake` JSON
/// (asset/asset_json.cpp) both take their key names from these tables and both call these
/// checks, so each range is written once; docs/config.md lists units and ranges per key.

#include <string>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// A value out of its range. key() is its path in config syntax ("camera.fx",
/// "rig.lights[1].rid.table.angle_deg[2]"), which is also the JSON path in the asset; each
/// reader adds where it read it (a YAML file and line, the asset's metadata).
class SchemaError : public ConfigError {
public:
    SchemaError(std::string key, std::string problem)
        : ConfigError(key + ": " + problem), m_key(std::move(key)), m_problem(std::move(problem)) {}
    const std::string& key() const { return m_key; }
    const std::string& problem() const { return m_problem; }

private:
    std::string m_key, m_problem;
};

/// The keys of each map of the schema, in the order the writers emit them. Readers accept no
/// others; writers write no others (tests/unit/io/config_test.cpp and asset_test check both).
namespace schema {
inline const std::vector<std::string> kSections = {"camera", "rig", "water", "snow"};
inline const std::vector<std::string> kCamera = {"width", "height", "fx", "fy", "cx", "cy"};
inline const std::vector<std::string> kRig = {"name", "lights"};
inline const std::vector<std::string> kLight = {"name", "position",   "direction", "intensity",
                                                "rid",  "cutoff_deg", "radius"};
inline const std::vector<std::string> kRid = {"gaussian", "table"};
inline const std::vector<std::string> kRidGaussian = {"sigma_deg"};
inline const std::vector<std::string> kRidTable = {"angle_deg", "value"};
/// `preset` only in YAML: the asset stores the resolved values.
inline const std::vector<std::string> kWater = {"name",       "preset", "attenuation",
                                                "scattering", "phase",  "forward_scatter"};
inline const std::vector<std::string> kPhase = {"petzold", "henyey_greenstein"};
inline const std::vector<std::string> kPhaseHg = {"g"};
inline const std::vector<std::string> kForwardScatter = {"G", "k"};
/// `preset` only in YAML: what is written is the values.
inline const std::vector<std::string> kSnow = {
    "preset", "concentration",  "d_min_mm", "d_max_mm",         "slope",
    "albedo", "max_distance_m", "streaks",  "exposure_time_ms", "frame_rate_hz"};
}  // namespace schema

/// The nearest a lamp may be to the camera centre, metres. The single-scattering backscatter
/// of a point lamp at distance r from the camera grows like 1/r (along a ray past it,
/// integral dt / (r^2 + t^2) = pi / (2 r)) and is infinite at r = 0, where the quadrature
/// returned 1e10-scale radiance or ran for minutes. Real lamps sit outside the camera's
/// housing, several centimetres from the lens at the least; within 2 cm a "lamp" is a modelling
/// mistake (a position forgotten at [0, 0, 0]), not a rig.
inline constexpr double kLampNearFieldRadius = 0.02;

/// The widest angle, per image axis, between the optical axis and the ray through any pixel
/// edge (u from -0.5 to width - 0.5, v from -0.5 to height - 0.5), degrees. A pinhole (a
/// rectilinear lens) of 160 degrees across is already wider than any real one (the widest
/// rectilinear lenses cover about 120 to 130 degrees; wider ones are fisheyes, which this
/// camera model does not describe), and every cost of a bake grows without bound toward 90
/// degrees: a ray's path is its depth / cos(phi) (8x at the corner of an 80 x 80 degree
/// camera, 1e4x at fx = 1e-4 on a 320-pixel image), the quadrature follows that path and the
/// frustum's width grows as tan. So fx 1e-4 .. 5e-324 and a cx far outside the image, which
/// ran for minutes and reached 12 GB, are refused here, before any work. The cameras of
/// volumes/ and the tests are at most 55 degrees per half axis.
inline constexpr double kMaxRayAngleDeg = 80.0;

/// Largest radiant intensity of a lamp per channel, W/sr. Real underwater lamps give 1 to 1e4
/// W/sr on their axis (a 1 kW HMI spot about 1e4); 1e9 leaves five orders of magnitude above
/// that and keeps every radiance the bake and the runtime form (intensity / d^2 with d >= 2 cm,
/// times a phase function and an exposure) far inside float range: 1e39 overflowed float to
/// inf and rendered NaN, 1e308 wrote an asset that render refused.
inline constexpr double kMaxLampIntensity = 1e9;

/// Farthest a lamp may be from the camera centre, metres. A rig is rigid hardware that moves
/// with the camera: lamps of ROVs, landers and towed sleds sit within a few metres, 100 m is far
/// beyond any of them, and even the clearest water (c about 0.02 / m) has attenuated a lamp's
/// light by e^-2 at that distance. A lamp at 1e300 m squared its distance to inf and rendered NaN.
inline constexpr double kMaxLampDistance = 100.0;

/// width, height > 0 (within core/image.h's limits); fx, fy > 0 and finite; cx, cy finite; and
/// every pixel edge's ray within kMaxRayAngleDeg of the axis per image axis. Throws SchemaError.
void validate(const Camera& camera);

/// At least one light, unique names; per light: a finite position at least kLampNearFieldRadius
/// and at most kMaxLampDistance from the camera centre, a finite non-zero direction (it need not
/// be unit: the YAML reader normalises after this check), intensity in [0, kMaxLampIntensity]
/// per channel, a Gaussian sigma > 0 or a table of
/// >= 2 strictly ascending angles in [0, 180] with as many values >= 0, cutoff in (0, 180],
/// radius in [0, kMaxLampRadius] metres.
void validate(const Rig& rig);

/// c >= 0, 0 <= b <= c per channel; Henyey-Greenstein g in (-1, 1); enabled forward scatter
/// with 0 <= G <= c and k >= 0.
void validate(const Water& water);

}  // namespace deepsea
