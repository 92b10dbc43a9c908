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
inline const std::vector<std::string> kSections = {"camera", "rig", "water"};
inline const std::vector<std::string> kCamera = {"width", "height", "fx", "fy", "cx", "cy"};
inline const std::vector<std::string> kRig = {"name", "lights"};
inline const std::vector<std::string> kLight = {"name",      "position", "direction",
                                                "intensity", "rid",      "cutoff_deg"};
inline const std::vector<std::string> kRid = {"gaussian", "table"};
inline const std::vector<std::string> kRidGaussian = {"sigma_deg"};
inline const std::vector<std::string> kRidTable = {"angle_deg", "value"};
/// `preset` only in YAML: the asset stores the resolved values.
inline const std::vector<std::string> kWater = {"name",       "preset", "attenuation",
                                                "scattering", "phase",  "forward_scatter"};
inline const std::vector<std::string> kPhase = {"petzold", "henyey_greenstein"};
inline const std::vector<std::string> kPhaseHg = {"g"};
inline const std::vector<std::string> kForwardScatter = {"G", "k"};
}  // namespace schema

/// The nearest a lamp may be to the camera centre, metres. The single-scattering backscatter
/// of a point lamp at distance r from the camera grows like 1/r (along a ray past it,
/// integral dt / (r^2 + t^2) = pi / (2 r)) and is infinite at r = 0, where the quadrature
/// returned 1e10-scale radiance or ran for minutes. Real lamps sit outside the camera's
/// housing, several centimetres from the lens at the least; within 2 cm a "lamp" is a modelling
/// mistake (a position forgotten at [0, 0, 0]), not a rig.
inline constexpr double kLampNearFieldRadius = 0.02;

/// width, height > 0; fx, fy > 0; cx, cy finite. Throws SchemaError.
void validate(const Camera& camera);

/// At least one light, unique names; per light: a finite position at least kLampNearFieldRadius
/// from the camera centre, a non-zero direction (it need not be unit: the
/// YAML reader normalises after this check), intensity >= 0, a Gaussian sigma > 0 or a table of
/// >= 2 strictly ascending angles in [0, 180] with as many values >= 0, cutoff in (0, 180].
void validate(const Rig& rig);

/// c >= 0, 0 <= b <= c per channel; Henyey-Greenstein g in (-1, 1); enabled forward scatter
/// with 0 <= G <= c and k >= 0.
void validate(const Water& water);

}  // namespace deepsea
