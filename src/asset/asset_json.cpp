#include "deepsea/asset/asset_json.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "deepsea/core/error.h"
#include "deepsea/core/hash.h"
#include "deepsea/optics/schema.h"
#include "higher_orders_json.h"
#include "json_fields.h"
#include "port_json.h"

namespace deepsea {

using json_fields::fail;
using json_fields::get;
using json_fields::integer;
using json_fields::num;
using nlohmann::json;

namespace {

json rgb_json(const Rgb& x) { return json::array({x.r, x.g, x.b}); }
json vec_json(const Vec3& x) { return json::array({x.x, x.y, x.z}); }

json camera_json(const Camera& c) {
    return {{"width", c.width}, {"height", c.height}, {"fx", c.fx},
            {"fy", c.fy},       {"cx", c.cx},         {"cy", c.cy}};
}

json rid_json(const Rid& r) {
    if (r.kind == Rid::Kind::Gaussian) return {{"gaussian", {{"sigma_deg", r.sigma_deg}}}};
    return {{"table", {{"angle_deg", r.angle_deg}, {"value", r.value}}}};
}

json rig_json(const Rig& rig) {
    json lights = json::array();
    for (const Light& l : rig.lights) {
        json lj = {{"name", l.name},
                   {"position", vec_json(l.position)},
                   {"direction", vec_json(l.direction)},
                   {"intensity", rgb_json(l.intensity)},
                   {"rid", rid_json(l.rid)},
                   {"cutoff_deg", l.rid.cutoff_deg}};
        // Only where it is not the default: assets (and their input hashes) of lamps with the
        // default radius stay as they were before lamps had one.
        if (l.radius != kDefaultLampRadius) lj["radius"] = l.radius;
        lights.push_back(std::move(lj));
    }
    return {{"name", rig.name}, {"lights", lights}};
}

json water_json(const Water& w) {
    json fs = "off";
    if (w.forward.enabled && w.forward.model == ForwardModel::PhaseFunction) {
        fs = "phase_function";
    } else if (w.forward.enabled) {
        fs = {{"G", rgb_json(w.forward.G)}, {"k", w.forward.k}};
    }
    json phase = to_string(w.phase.kind);
    if (w.phase.kind == PhaseKind::HenyeyGreenstein) {
        phase = {{"henyey_greenstein", {{"g", w.phase.g}}}};
    }
    return {{"name", w.name},
            {"attenuation", rgb_json(w.c)},
            {"scattering", rgb_json(w.b)},
            {"phase", phase},
            {"forward_scatter", fs}};
}

json quadrature_json(const Quadrature& q) {
    return {{"rel_tol", q.rel_tol}, {"abs_tol", q.abs_tol}, {"max_depth", q.max_depth}};
}

/// What the user asked for: the hash covers exactly these plus camera, rig and water.
json settings_json(const BakeInfo& info) {
    const Lattice& l = info.lattice;
    // Automatic choices hash as "auto": the request, not what the check refined it to.
    json s = {{"step", info.step_auto ? json("auto") : json(l.step)},
              {"depth_scheme", to_string(l.scheme)},
              {"depth_samples", info.depth_samples_auto ? json("auto") : json(l.slabs())},
              {"quadrature", quadrature_json(info.quadrature)}};
    // Without the check an automatic lattice is never refined: another request.
    if ((info.step_auto || info.depth_samples_auto) && !info.check.done) s["check"] = "off";
    if (l.scheme == DepthScheme::Log) s["z0"] = l.z0;
    // Single-scattering assets hash as before this setting existed.
    if (info.scattering == Scattering::Multiple) {
        s["scattering"] = to_string(info.scattering);
        s["paths"] = info.higher_orders.paths;
        // "auto" was 64 px / step before the angular rule: another request.
        s["stride"] =
            info.higher_orders.stride_auto ? json("angular") : json(info.higher_orders.stride);
        s["seed"] = info.higher_orders.seed;
        s["lamp_samples"] = info.higher_orders.lamp_samples;
        // the wall model: assets baked before it are another request, re-baked by bake-library
        if (info.higher_orders.wall) s["wall"] = "absorbing";
        // tail pooling: assets baked before it are another request too
        if (info.higher_orders.tail_above > 0.0) {
            s["tail"] = {info.higher_orders.tail_above, info.higher_orders.tail_radius};
            // the threshold from the column's own mean: another request again
            if (info.higher_orders.tail_of_mean > 0.0)
                s["tail"].push_back(info.higher_orders.tail_of_mean);
        }
        if (info.higher_orders.log_between) s["between_columns"] = "log-bilinear";
        if (info.higher_orders.lamp_symmetric) s["lamp_symmetry"] = "mirror";
        // the roulette after each segment's next event: another estimate, so another request
        if (info.higher_orders.roulette_after_next_event) s["roulette"] = "after next event";
    }
    if (info.z_max_auto) {
        s["z_max"] = "auto";
        s["tolerance"] = info.tolerance;
    } else {
        s["z_max"] = l.z_max();
    }
    return s;
}

// --- parsing -------------------------------------------------------------------------------

std::string str(const json& j, const char* key, const std::string& where) {
    const json& x = get(j, key, where);
    if (!x.is_string()) fail(where + "." + key, "not a string");
    return x.get<std::string>();
}

std::vector<double> numbers(const json& x, const std::string& where) {
    if (!x.is_array()) fail(where, "not an array");
    std::vector<double> out;
    for (const json& e : x) {
        if (!e.is_number()) fail(where, "not an array of numbers");
        out.push_back(e.get<double>());
    }
    return out;
}

Rgb rgb(const json& j, const char* key, const std::string& where) {
    const auto v = numbers(get(j, key, where), where + "." + key);
    if (v.size() != 3) fail(where + "." + key, "needs 3 numbers");
    return {v[0], v[1], v[2]};
}

Vec3 vec(const json& j, const char* key, const std::string& where) {
    const Rgb v = rgb(j, key, where);
    return {v.r, v.g, v.b};
}

Camera parse_camera(const json& j) {
    Camera c;
    c.width = integer(j, "width", "camera");
    c.height = integer(j, "height", "camera");
    c.fx = num(j, "fx", "camera");
    c.fy = num(j, "fy", "camera");
    c.cx = num(j, "cx", "camera");
    c.cy = num(j, "cy", "camera");
    return c;
}

Rid parse_rid(const json& j, const std::string& where) {
    Rid r;
    if (j.is_object() && j.contains("gaussian")) {
        r.kind = Rid::Kind::Gaussian;
        r.sigma_deg = num(j["gaussian"], "sigma_deg", where + ".gaussian");
    } else if (j.is_object() && j.contains("table")) {
        r.kind = Rid::Kind::Table;
        r.angle_deg = numbers(get(j["table"], "angle_deg", where), where + ".table.angle_deg");
        r.value = numbers(get(j["table"], "value", where), where + ".table.value");
    } else {
        fail(where, "neither gaussian nor table");
    }
    return r;
}

Rig parse_rig(const json& j) {
    Rig rig;
    rig.name = str(j, "name", "rig");
    const json& lights = get(j, "lights", "rig");
    if (!lights.is_array()) fail("rig.lights", "not an array");
    for (std::size_t n = 0; n < lights.size(); ++n) {
        const std::string where = "rig.lights[" + std::to_string(n) + "]";
        const json& lj = lights[n];
        Light l;
        l.name = str(lj, "name", where);
        l.position = vec(lj, "position", where);
        l.direction = vec(lj, "direction", where);
        l.intensity = rgb(lj, "intensity", where);
        l.rid = parse_rid(get(lj, "rid", where), where + ".rid");
        l.rid.cutoff_deg = num(lj, "cutoff_deg", where);
        // Assets from before lamps had a radius, and lamps of the default one, have none.
        if (lj.contains("radius")) l.radius = num(lj, "radius", where);
        rig.lights.push_back(std::move(l));
    }
    return rig;
}

Phase parse_phase(const json& j) {
    Phase p;
    if (j.is_object() && j.contains("henyey_greenstein")) {
        p.kind = PhaseKind::HenyeyGreenstein;
        p.g = num(j["henyey_greenstein"], "g", "water.phase.henyey_greenstein");
        return p;
    }
    if (!j.is_string()) fail("water.phase", "not a phase function");
    const std::string name = j.get<std::string>();
    for (PhaseKind k : {PhaseKind::Isotropic, PhaseKind::HenyeyGreenstein, PhaseKind::PetzoldClear,
                        PhaseKind::PetzoldCoastal, PhaseKind::PetzoldTurbid}) {
        if (name == to_string(k)) {
            p.kind = k;
            return p;
        }
    }
    fail("water.phase", "unknown phase function '" + name + "'");
}

Water parse_water(const json& j) {
    Water w;
    w.name = str(j, "name", "water");
    w.c = rgb(j, "attenuation", "water");
    w.b = rgb(j, "scattering", "water");
    w.phase = parse_phase(get(j, "phase", "water"));
    const json& fs = get(j, "forward_scatter", "water");
    if (fs.is_object()) {
        w.forward.enabled = true;
        w.forward.G = rgb(fs, "G", "water.forward_scatter");
        w.forward.k = num(fs, "k", "water.forward_scatter");
    } else if (fs.is_string() && fs.get<std::string>() == "phase_function") {
        w.forward = phase_function_forward_scatter();
    } else if (!(fs.is_string() && fs.get<std::string>() == "off")) {
        fail("water.forward_scatter", "neither 'off', 'phase_function' nor {G, k}");
    }
    return w;
}

std::string hex64(std::uint64_t h) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
    return buf;
}

}  // namespace

std::string bake_info_to_json(const BakeInfo& info, int indent) {
    const Lattice& l = info.lattice;
    json lattice = {{"step", l.step},
                    {"columns", l.ni},
                    {"rows", l.nj},
                    {"depth_scheme", to_string(l.scheme)},
                    {"depth_samples", l.slabs()},
                    {"z_max", l.z_max()},
                    {"z_max_auto", info.z_max_auto},
                    {"step_auto", info.step_auto},
                    {"depth_samples_auto", info.depth_samples_auto},
                    {"tolerance", info.tolerance},
                    {"z", l.z}};
    if (l.scheme == DepthScheme::Log) lattice["z0"] = l.z0;
    json j = {{"format", kAssetFormat},
              {"baker_version", info.baker_version},
              {"input_hash", info.input_hash},
              {"camera", camera_json(info.camera)},
              {"rig", rig_json(info.rig)},
              {"water", water_json(info.water)},
              {"lattice", lattice},
              {"quadrature", quadrature_json(info.quadrature)},
              {"scattering", to_string(info.scattering)}};
    if (info.port) j["port"] = port_json(*info.port);  // none: pinhole columns
    if (info.scattering == Scattering::Multiple) {
        j["multiple_scattering"] = higher_orders_json(info.higher_orders);
    }
    if (info.check.done) {
        const LatticeCheck& c = info.check;
        j["check"] = {{"mean_rel", c.mean_rel},
                      {"max_rel", c.max_rel},
                      {"max_pixel", {c.max_u, c.max_v}},
                      {"columns_mean_rel", c.columns_mean_rel},
                      {"columns_max_rel", c.columns_max_rel},
                      {"pixels", c.pixels},
                      {"refinements", c.refinements}};
    }
    return j.dump(indent);
}

BakeInfo bake_info_from_json(const std::string& text) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        throw AssetError(std::string("deepsea:bake: not valid JSON (") + e.what() + ")");
    }
    if (!j.is_object()) fail("(top)", "not an object");
    BakeInfo info;
    info.baker_version = str(j, "baker_version", "(top)");
    info.input_hash = str(j, "input_hash", "(top)");
    info.camera = parse_camera(get(j, "camera", "(top)"));
    info.rig = parse_rig(get(j, "rig", "(top)"));
    info.water = parse_water(get(j, "water", "(top)"));
    try {
        // The same range checks as the YAML configs (optics/schema.h): a damaged or hand-edited
        // asset is refused here rather than rendering nonsense.
        validate(info.camera);
        validate(info.rig);
        validate(info.water);
    } catch (const SchemaError& e) {
        fail(e.key(), e.problem());
    }

    // Assets from before ports have none: pinhole columns.
    if (j.contains("port")) info.port = parse_port(j["port"]);

    const json& lj = get(j, "lattice", "(top)");
    info.z_max_auto = get(lj, "z_max_auto", "lattice").is_boolean() && lj["z_max_auto"].get<bool>();
    info.tolerance = num(lj, "tolerance", "lattice");
    // Assets from before the automatic lattice have neither flag: their lattice was given.
    const auto flag = [](const json& o, const char* key) {
        return o.contains(key) && o[key].is_boolean() && o[key].get<bool>();
    };
    info.step_auto = flag(lj, "step_auto");
    info.depth_samples_auto = flag(lj, "depth_samples_auto");
    const DepthScheme scheme = [&] {
        try {
            return parse_depth_scheme(str(lj, "depth_scheme", "lattice"));
        } catch (const ConfigError& e) {
            fail("lattice.depth_scheme", e.what());
        }
    }();
    const double z0 = lj.contains("z0") ? num(lj, "z0", "lattice") : kDefaultLogZ0;
    std::vector<double> z = numbers(get(lj, "z", "lattice"), "lattice.z");
    Camera cam = info.camera;
    const int step = integer(lj, "step", "lattice");
    try {
        info.lattice = make_lattice(cam, step, scheme, std::move(z), z0);
    } catch (const ConfigError& e) {
        fail("lattice", e.what());
    }
    if (info.lattice.ni != integer(lj, "columns", "lattice") ||
        info.lattice.nj != integer(lj, "rows", "lattice")) {
        fail("lattice", "columns/rows do not match the camera and step");
    }
    const json& q = get(j, "quadrature", "(top)");
    info.quadrature.rel_tol = num(q, "rel_tol", "quadrature");
    info.quadrature.abs_tol = num(q, "abs_tol", "quadrature");
    info.quadrature.max_depth = integer(q, "max_depth", "quadrature");
    // Assets from before multiple scattering existed hold single scattering.
    if (j.contains("scattering")) {
        try {
            info.scattering = parse_scattering(str(j, "scattering", "(top)"));
        } catch (const ConfigError& e) {
            fail("scattering", e.what());
        }
    }
    if (info.scattering == Scattering::Multiple) {
        info.higher_orders = parse_higher_orders(get(j, "multiple_scattering", "(top)"));
    }
    if (j.contains("check")) {
        const json& cj = j["check"];
        LatticeCheck& c = info.check;
        c.done = true;
        c.mean_rel = num(cj, "mean_rel", "check");
        c.max_rel = num(cj, "max_rel", "check");
        const std::vector<double> at = numbers(get(cj, "max_pixel", "check"), "check.max_pixel");
        if (at.size() != 2) fail("check.max_pixel", "not two numbers");
        c.max_u = int(at[0]);
        c.max_v = int(at[1]);
        c.columns_mean_rel = num(cj, "columns_mean_rel", "check");
        c.columns_max_rel = num(cj, "columns_max_rel", "check");
        c.pixels = integer(cj, "pixels", "check");
        c.refinements = integer(cj, "refinements", "check");
        if (!(c.mean_rel >= 0.0 && c.max_rel >= c.mean_rel && c.pixels >= 1)) {
            fail("check", "errors must be >= 0 (max >= mean) over >= 1 pixel");
        }
    }
    return info;
}

std::string input_hash(const BakeInfo& info) {
    json j = {{"camera", camera_json(info.camera)},
              {"rig", rig_json(info.rig)},
              {"water", water_json(info.water)},
              {"settings", settings_json(info)}};
    // Only with a port: assets without one hash as before ports existed.
    if (info.port) j["port"] = port_json(*info.port);
    // nlohmann's objects keep keys sorted, so dump() is canonical for equal inputs.
    const std::string text = j.dump();
    return "fnv1a64:" + hex64(fnv1a64(text));
}

namespace {

/// A JSON string literal: paths may hold quotes, backslashes or control characters.
std::string json_string(const std::string& text) {
    std::string out = "\"";
    for (unsigned char ch : text) {
        if (ch == '"' || ch == '\\') {
            out += '\\';
            out += char(ch);
        } else if (ch < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", ch);
            out += buf;
        } else {
            out += char(ch);
        }
    }
    return out + "\"";
}

}  // namespace

std::pair<Rgb, Rgb> backscatter_range(const Asset& asset) {
    const Lattice& l = asset.lattice();
    Rgb lo(1e30), hi(0.0);
    for (int i = 0; i < l.ni; ++i) {
        for (int j = 0; j < l.nj; ++j) {
            const Rgb v = asset.at(i, j, l.slabs());
            for (int c = 0; c < 3; ++c) {
                lo[c] = std::min(lo[c], v[c]);
                hi[c] = std::max(hi[c], v[c]);
            }
        }
    }
    return {lo, hi};
}

std::string asset_info_json(const std::string& path, const AssetFileSummary& s,
                            const Asset& asset) {
    const auto [lo, hi] = backscatter_range(asset);
    const auto vec = [](const Vec3& v) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "[%.9g, %.9g, %.9g]", v.x, v.y, v.z);
        return std::string(buf);
    };
    std::string grids;
    for (const GridSummary& g : s.grids) {
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      "%s{\"name\": %s, \"value_type\": %s, \"transform\": %s, \"half\": %s, "
                      "\"active_voxels\": %lld, ",
                      grids.empty() ? "" : ", ", json_string(g.name).c_str(),
                      json_string(g.value_type).c_str(), json_string(g.transform).c_str(),
                      g.half ? "true" : "false", static_cast<long long>(g.active_voxels));
        grids += buf;
        grids += "\"world_min\": " + vec(g.world_min) + ", \"world_max\": " + vec(g.world_max) +
                 ", \"leaf_world_min\": " + vec(g.leaf_world_min) +
                 ", \"leaf_world_max\": " + vec(g.leaf_world_max) + "}";
    }
    const WorldBox box = frustum_extent(s.info.camera, s.info.lattice.z_max());
    const std::string head = "{\"file\": " + json_string(path) + ", ";
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "\"bytes\": %ju, \"format\": %d, \"value_scale\": %.17g, "
                  "\"backscatter_at_z_max\": {\"min\": [%.9g, %.9g, %.9g], "
                  "\"max\": [%.9g, %.9g, %.9g]}, \"frustum_extent\": {\"min\": %s, \"max\": %s}, "
                  "\"preview_voxel_size\": %.9g, \"grids\": [",
                  s.file_bytes, s.format, s.value_scale, lo.r, lo.g, lo.b, hi.r, hi.g, hi.b,
                  vec(box.min).c_str(), vec(box.max).c_str(), s.preview_voxel_size);
    // Which forward scatter the runtime blurs with: the asset's table, or the small-angle
    // model (null).
    std::string psf = "null";
    if (const auto& t = asset.forward_psf) {
        char pb[256];
        std::snprintf(pb, sizeof pb,
                      "{\"depths\": %d, \"rings\": %d, \"far_depth\": %.9g, \"paths\": %d, "
                      "\"seed\": %llu}",
                      t->depths(), t->rings(), t->depth.back(), t->paths,
                      static_cast<unsigned long long>(t->seed));
        psf = pb;
    }
    return head + buf + grids + "], \"forward_psf\": " + psf +
           ", \"bake\": " + bake_info_to_json(s.info, -1) + "}";
}

}  // namespace deepsea
