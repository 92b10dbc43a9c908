#include "port_json.h"

#include <string>

#include "deepsea/core/error.h"
#include "deepsea/optics/schema.h"
#include "json_fields.h"

namespace deepsea {

using json_fields::fail;
using json_fields::get;
using json_fields::integer;
using json_fields::num;
using nlohmann::json;

namespace {

json triple(double x, double y, double z) { return json::array({x, y, z}); }

Vec3 three(const json& j, const char* key, const std::string& where) {
    const json& x = get(j, key, where);
    if (!x.is_array() || x.size() != 3) fail(where + "." + key, "needs 3 numbers");
    for (const json& e : x)
        if (!e.is_number()) fail(where + "." + key, "needs 3 numbers");
    return {x[0].get<double>(), x[1].get<double>(), x[2].get<double>()};
}

}  // namespace

json port_json(const Port& p) {
    json side = {{"glass_thickness",
                  p.kind == PortKind::Flat ? p.flat.glass_thickness : p.dome.glass_thickness},
                 {"n_air", p.n_air},
                 {"n_glass", p.n_glass},
                 {"n_water", triple(p.n_water.r, p.n_water.g, p.n_water.b)}};
    if (p.kind == PortKind::Flat) {
        side["normal"] = triple(p.flat.normal.x, p.flat.normal.y, p.flat.normal.z);
        side["distance"] = p.flat.distance;
    } else {
        side["centre"] = triple(p.dome.centre.x, p.dome.centre.y, p.dome.centre.z);
        side["radius"] = p.dome.radius;
    }
    return {{p.name(), side}, {"fresnel", p.fresnel}};
}

Port parse_port(const json& j) {
    if (!j.is_object()) fail("port", "not an object");
    Port p;
    const bool flat = j.contains("flat"), dome = j.contains("dome");
    if (flat == dome) fail("port", "needs exactly one of flat and dome");
    p.kind = flat ? PortKind::Flat : PortKind::Dome;
    const std::string where = std::string("port.") + p.name();
    const json& s = j[p.name()];
    if (flat) {
        p.flat.normal = three(s, "normal", where);
        p.flat.distance = num(s, "distance", where);
        p.flat.glass_thickness = num(s, "glass_thickness", where);
    } else {
        p.dome.centre = three(s, "centre", where);
        p.dome.radius = num(s, "radius", where);
        p.dome.glass_thickness = num(s, "glass_thickness", where);
    }
    p.n_air = num(s, "n_air", where);
    p.n_glass = num(s, "n_glass", where);
    const Vec3 nw = three(s, "n_water", where);
    p.n_water = {nw.x, nw.y, nw.z};
    const json& fresnel = get(j, "fresnel", "port");
    if (!fresnel.is_boolean()) fail("port.fresnel", "not true or false");
    p.fresnel = fresnel.get<bool>();
    try {
        validate(p);  // the YAML's range checks: a damaged asset is refused, not rendered
    } catch (const SchemaError& e) {
        std::string key = e.key();
        if (key.rfind("camera.", 0) == 0) key = key.substr(7);
        fail(key, e.problem());
    }
    return p;
}

}  // namespace deepsea
