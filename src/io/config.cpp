#include "deepsea/io/config.h"

#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "camera_config.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/schema.h"
#include "deepsea/optics/water_presets.h"
#include "port_config.h"
#include "snow_config.h"
#include "yaml_reader.h"

namespace deepsea {

namespace {

using yaml::Document;
using yaml::Field;
using yaml::fmt;
using yaml::join;
using yaml::MapView;

/// Scattering albedo b/c used when a config gives `attenuation` without `scattering` and no
/// preset: the mean band albedo of the six Jerlov presets (0.66; they range from 0.23 in the
/// red of clear ocean water to 0.87 in the green of turbid coastal water). A user who knows b
/// should give it; this keeps a c-only config usable with a plausible amount of backscatter.
constexpr double kDefaultAlbedo = 0.66;

// The key names and every range check live in optics/schema.h, shared with the asset's JSON;
// this file maps YAML onto the structs (types, required keys, defaults, presets) and then
// calls validate(), whose errors Document::fail reports at the offending line.

// ---------------------------------------------------------------------------------------------
// camera
//
//   key     unit    range     required
//   width   pixels  int > 0   yes
//   height  pixels  int > 0   yes
//   fx, fy  pixels  > 0       yes
//   cx, cy  pixels  any       yes   (pixel centres at integer coordinates, docs/model.md)

//   lens, sensor, processing: the camera stage (camera_config.cpp); optional
//   port: the housing's flat or dome port (port_config.cpp); optional

/// The keys of the YAML camera section: the pinhole's (schema::kCamera, also the asset's), the
/// camera stage's and the port.
const std::vector<std::string>& camera_keys() {
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k = schema::kCamera;
        k.insert(k.end(), camera_schema::kCameraModel.begin(), camera_schema::kCameraModel.end());
        k.push_back("port");
        return k;
    }();
    return keys;
}

Camera parse_camera(const Document& doc, const Field& f, std::optional<CameraModel>& model,
                    std::optional<Port>& port) {
    const MapView m(doc, f, camera_keys());
    Camera cam;
    cam.width = doc.integer(m.need("width"));
    cam.height = doc.integer(m.need("height"));
    cam.fx = doc.number(m.need("fx"));
    cam.fy = doc.number(m.need("fy"));
    cam.cx = doc.number(m.need("cx"));
    cam.cy = doc.number(m.need("cy"));
    validate(cam);
    model = parse_camera_model(doc, m, cam);
    port = parse_port(doc, m, cam);
    return cam;
}

// ---------------------------------------------------------------------------------------------
// rig
//
//   key                     unit     range                            required / default
//   name                    -        string                           "" (empty)
//   lights                  -        non-empty list                   yes
//   lights[i].name          -        string, unique in the rig        light<i+1>
//   lights[i].position      m        [x, y, z], camera frame          yes
//   lights[i].direction     -        [x, y, z], non-zero; normalised  yes
//   lights[i].intensity     W/sr     [r, g, b], each >= 0             yes
//   lights[i].rid           -        {gaussian: {sigma_deg}} or       {gaussian: {sigma_deg: 35}}
//                                    {table: {angle_deg, value}}
//     gaussian.sigma_deg    degrees  > 0                              yes
//     table.angle_deg       degrees  >= 2 entries, strictly ascending, in [0, 180]
//     table.value           -        same length as angle_deg, each >= 0
//   lights[i].cutoff_deg    degrees  (0, 180]                         180 (no cutoff)
//   lights[i].radius        m        [0, 0.5], the emitting face      0.04 (kDefaultLampRadius)

Rid parse_rid(const Document& doc, const Field& f) {
    const MapView m(doc, f, schema::kRid);
    if (m.has("gaussian") == m.has("table"))
        doc.fail(f, "give exactly one of " + join(schema::kRid));
    Rid rid;
    if (const Field* g = m.opt("gaussian")) {
        rid.kind = Rid::Kind::Gaussian;
        rid.sigma_deg = doc.number(MapView(doc, *g, schema::kRidGaussian).need("sigma_deg"));
        return rid;
    }
    const MapView tm(doc, *m.opt("table"), schema::kRidTable);
    rid.kind = Rid::Kind::Table;
    for (const Field& a : doc.list(tm.need("angle_deg"))) rid.angle_deg.push_back(doc.number(a));
    for (const Field& v : doc.list(tm.need("value"))) rid.value.push_back(doc.number(v));
    return rid;
}

/// The light as written: its direction is normalised only after validate() has checked it.
Light parse_light(const Document& doc, const Field& f, std::size_t index) {
    const MapView m(doc, f, schema::kLight);
    Light l;
    const Field* name = m.opt("name");
    l.name = name ? doc.string(*name) : "light" + std::to_string(index + 1);
    l.position = doc.vec3(m.need("position"));
    l.direction = doc.vec3(m.need("direction"));
    l.intensity = doc.rgb(m.need("intensity"));
    if (const Field* r = m.opt("rid")) l.rid = parse_rid(doc, *r);
    if (const Field* c = m.opt("cutoff_deg")) l.rid.cutoff_deg = doc.number(*c);
    if (const Field* r = m.opt("radius")) l.radius = doc.number(*r);
    return l;
}

Rig parse_rig(const Document& doc, const Field& f) {
    const MapView m(doc, f, schema::kRig);
    Rig rig;
    if (const Field* n = m.opt("name")) rig.name = doc.string(*n);
    const auto items = doc.list(m.need("lights"));
    for (std::size_t i = 0; i < items.size(); ++i)
        rig.lights.push_back(parse_light(doc, items[i], i));
    validate(rig);
    for (Light& l : rig.lights) l.direction = normalize(l.direction);
    return rig;
}

// ---------------------------------------------------------------------------------------------
// water
//
//   key              unit   range                               default
//   name             -      string                              the preset's, else "custom"
//   preset           -      jerlov:<IB|II|III|1C|3C|5C>         none
//                           | deep:<clear|moderate|nepheloid>
//   attenuation      1/m    [r, g, b], each >= 0 (c)            the preset's; required without
//   scattering       1/m    [r, g, b], 0 <= b <= c per channel  the preset's albedo b/c times c,
//                                                               else 0.66 c (kDefaultAlbedo)
//   phase            -      isotropic | {petzold: clear|coastal|turbid}
//                           | {henyey_greenstein: {g: (-1, 1)}} the preset's, else petzold clear
//   forward_scatter  -      off | on | {G: [r, g, b] 1/m, 0 <= G <= c; k: rad/m >= 0}    off
//                           (on: the point spread of the phase function, optics/forward_psf.h;
//                            {G, k}: Jaffe-McGlamery as in the paper)

Phase parse_phase(const Document& doc, const Field& f) {
    Phase p;
    if (f.node.IsScalar()) {
        // The names of to_string(PhaseKind) are accepted as plain scalars as well.
        const std::string s = f.node.Scalar();
        if (s == "isotropic")
            p.kind = PhaseKind::Isotropic;
        else if (s == "petzold:clear")
            p.kind = PhaseKind::PetzoldClear;
        else if (s == "petzold:coastal")
            p.kind = PhaseKind::PetzoldCoastal;
        else if (s == "petzold:turbid")
            p.kind = PhaseKind::PetzoldTurbid;
        else
            doc.fail(f, "unknown phase function '" + s +
                            "' (expected isotropic, {petzold: clear|coastal|turbid} or "
                            "{henyey_greenstein: {g: ..}})");
        return p;
    }
    const MapView m(doc, f, schema::kPhase);
    if (m.has("petzold") == m.has("henyey_greenstein"))
        doc.fail(f, "give exactly one of " + join(schema::kPhase));
    if (const Field* pz = m.opt("petzold")) {
        const std::string s = doc.string(*pz);
        if (s == "clear")
            p.kind = PhaseKind::PetzoldClear;
        else if (s == "coastal")
            p.kind = PhaseKind::PetzoldCoastal;
        else if (s == "turbid")
            p.kind = PhaseKind::PetzoldTurbid;
        else
            doc.fail(*pz, "expected clear, coastal or turbid, got '" + s + "'");
        return p;
    }
    p.kind = PhaseKind::HenyeyGreenstein;
    p.g = doc.number(MapView(doc, *m.opt("henyey_greenstein"), schema::kPhaseHg).need("g"));
    return p;
}

Water parse_water(const Document& doc, const Field& f) {
    const MapView m(doc, f, schema::kWater);
    Water w;
    w.name = "custom";
    w.phase.kind = PhaseKind::PetzoldClear;
    const Field* preset = m.opt("preset");
    if (preset) {
        try {
            w = water_preset(doc.string(*preset));
        } catch (const ConfigError& e) {
            doc.fail(*preset, e.what());
        }
    }
    const Rgb preset_c = w.c, preset_b = w.b;
    const Field* att = m.opt("attenuation");
    if (att)
        w.c = doc.rgb(*att);
    else if (!preset)
        m.need("attenuation");  // throws: required without a preset

    if (const Field* sca = m.opt("scattering")) {
        w.b = doc.rgb(*sca);
    } else if (!preset) {
        w.b = w.c * kDefaultAlbedo;
    } else if (att) {
        // New c on a preset: keep the preset's single-scattering albedo b/c per channel.
        for (int i = 0; i < 3; ++i)
            w.b[i] = preset_c[i] > 0.0 ? w.c[i] * preset_b[i] / preset_c[i] : 0.0;
    }
    if (const Field* ph = m.opt("phase")) w.phase = parse_phase(doc, *ph);
    if (const Field* n = m.opt("name")) w.name = doc.string(*n);

    if (const Field* fw = m.opt("forward_scatter")) {
        if (fw->node.IsScalar()) {
            const std::string s = fw->node.Scalar();
            if (s == "off" || s == "false") {
                w.forward = ForwardScatter{};
            } else if (s == "on" || s == "true") {
                w.forward = phase_function_forward_scatter();
            } else {
                doc.fail(*fw, "expected off, on or {G: [r, g, b], k: ..}, got '" + s + "'");
            }
        } else {
            const MapView fm(doc, *fw, schema::kForwardScatter);
            w.forward.enabled = true;
            w.forward.G = doc.rgb(fm.need("G"));
            w.forward.k = doc.number(fm.need("k"));
        }
    }
    validate(w);
    return w;
}

// ---------------------------------------------------------------------------------------------
// Documents and files.

struct Parsed {
    Setup setup;
    std::map<std::string, int> line;  ///< line of each section found
};

Parsed parse_document(const Document& doc) {
    Parsed out;
    try {
        static const char* const kEmpty =
            "empty configuration (expected camera, rig, water and/or snow sections)";
        if (doc.empty()) doc.fail(YAML::Mark::null_mark(), "", kEmpty);
        const MapView m(doc, doc.root(), schema::kSections);
        const Field *c = m.opt("camera"), *r = m.opt("rig"), *w = m.opt("water"),
                    *sn = m.opt("snow");
        // A map with none of the sections (`{}`) is as empty as no text: refused alike, so that
        // whatever parses also prints as a configuration that parses (fuzz_config's property).
        if (!c && !r && !w && !sn) doc.fail(doc.root().mark, "", kEmpty);
        if (c) {
            out.setup.camera = parse_camera(doc, *c, out.setup.camera_model, out.setup.port);
            out.line["camera"] = yaml::line_of(c->key_mark);
        }
        if (r) {
            out.setup.rig = parse_rig(doc, *r);
            out.line["rig"] = yaml::line_of(r->key_mark);
        }
        if (w) {
            out.setup.water = parse_water(doc, *w);
            out.line["water"] = yaml::line_of(w->key_mark);
        }
        if (sn) {
            out.setup.snow = parse_snow(doc, *sn);
            out.line["snow"] = yaml::line_of(sn->key_mark);
        }
    } catch (const SchemaError& e) {
        doc.fail(e);
    } catch (const YAML::Exception& e) {
        // Should not happen after the checks above; keep the one-line file:line format anyway.
        throw ConfigError(doc.file() + ":" + std::to_string(yaml::line_of(e.mark)) + ": " + e.msg);
    }
    return out;
}

std::string quote(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        if (c == '\n') {
            out += "\\n";
            continue;
        }
        out += c;
    }
    return out + "\"";
}

std::string triple(double a, double b, double c) {
    return "[" + fmt(a) + ", " + fmt(b) + ", " + fmt(c) + "]";
}

}  // namespace

Setup parse_setup(const std::string& yaml_text, const std::string& file_name) {
    return parse_document(Document(yaml_text, file_name)).setup;
}

Setup load_setup(const std::vector<std::string>& files) {
    Setup all;
    std::map<std::string, std::string> where;  // section -> "file:line" of its first definition
    for (const auto& file : files) {
        Parsed p = parse_document(Document::load(file));
        auto merge = [&](auto& dst, auto& src, const char* name) {
            if (!src) return;
            const std::string here = file + ":" + std::to_string(p.line[name]);
            if (dst)
                throw ConfigError(here + ": " + name + ": section given twice (first in " +
                                  where[name] + ")");
            dst = std::move(src);
            where[name] = here;
        };
        if (p.setup.camera) {  // the camera section's stage and port come with it
            all.camera_model = std::move(p.setup.camera_model);
            all.port = std::move(p.setup.port);
        }
        merge(all.camera, p.setup.camera, "camera");
        merge(all.rig, p.setup.rig, "rig");
        merge(all.water, p.setup.water, "water");
        merge(all.snow, p.setup.snow, "snow");
    }
    return all;
}

Water load_water(const std::string& spec) {
    if (is_water_preset(spec)) return water_preset(spec);
    Parsed p = parse_document(Document::load(spec));
    for (const char* other : {"camera", "rig"})
        if (p.line.count(other))
            throw ConfigError(spec + ":" + std::to_string(p.line[other]) + ": " + other +
                              ": a water file may hold only the water section");
    if (!p.setup.water) throw ConfigError(spec + ":1: water: missing section");
    return *p.setup.water;
}

void require_complete(const Setup& setup, const std::string& where) {
    std::vector<std::string> missing;
    if (!setup.camera) missing.push_back("camera");
    if (!setup.rig) missing.push_back("rig");
    if (!setup.water) missing.push_back("water");
    if (!missing.empty())
        throw ConfigError(where + ": missing section" + (missing.size() > 1 ? "s " : " ") +
                          join(missing) + " (give them in the config files)");
}

void refuse_port(const Setup& setup, const std::string& where, const std::string& what) {
    if (setup.port)
        throw ConfigError(where + ": camera.port: " + what +
                          ", and this command would ignore the port (docs/ports.md): remove "
                          "the port section");
}

std::string setup_to_yaml(const Setup& s) {
    std::ostringstream o;
    if (s.camera) {
        const Camera& c = *s.camera;
        o << "camera:\n"
          << "  width: " << c.width << "\n"
          << "  height: " << c.height << "\n"
          << "  fx: " << fmt(c.fx) << "\n"
          << "  fy: " << fmt(c.fy) << "\n"
          << "  cx: " << fmt(c.cx) << "\n"
          << "  cy: " << fmt(c.cy) << "\n";
        if (s.camera_model) write_camera_model(o, *s.camera_model);
        if (s.port) write_port(o, *s.port);
    }
    if (s.rig) {
        o << "rig:\n";
        if (!s.rig->name.empty()) o << "  name: " << quote(s.rig->name) << "\n";
        o << "  lights:\n";
        for (const Light& l : s.rig->lights) {
            o << "    - name: " << quote(l.name) << "\n"
              << "      position: " << triple(l.position.x, l.position.y, l.position.z) << "\n"
              << "      direction: " << triple(l.direction.x, l.direction.y, l.direction.z) << "\n"
              << "      intensity: " << triple(l.intensity.r, l.intensity.g, l.intensity.b) << "\n";
            if (l.rid.kind == Rid::Kind::Gaussian) {
                o << "      rid: {gaussian: {sigma_deg: " << fmt(l.rid.sigma_deg) << "}}\n";
            } else {
                std::vector<std::string> a, v;
                for (double x : l.rid.angle_deg) a.push_back(fmt(x));
                for (double x : l.rid.value) v.push_back(fmt(x));
                o << "      rid: {table: {angle_deg: [" << join(a) << "], value: [" << join(v)
                  << "]}}\n";
            }
            if (l.rid.cutoff_deg < 180.0)
                o << "      cutoff_deg: " << fmt(l.rid.cutoff_deg) << "\n";
            if (l.radius != kDefaultLampRadius) o << "      radius: " << fmt(l.radius) << "\n";
        }
    }
    if (s.water) {
        const Water& w = *s.water;
        o << "water:\n"
          << "  name: " << quote(w.name) << "\n"
          << "  attenuation: " << triple(w.c.r, w.c.g, w.c.b) << "\n"
          << "  scattering: " << triple(w.b.r, w.b.g, w.b.b) << "\n"
          << "  phase: ";
        switch (w.phase.kind) {
            case PhaseKind::Isotropic:
                o << "isotropic\n";
                break;
            case PhaseKind::HenyeyGreenstein:
                o << "{henyey_greenstein: {g: " << fmt(w.phase.g) << "}}\n";
                break;
            case PhaseKind::PetzoldClear:
                o << "{petzold: clear}\n";
                break;
            case PhaseKind::PetzoldCoastal:
                o << "{petzold: coastal}\n";
                break;
            case PhaseKind::PetzoldTurbid:
                o << "{petzold: turbid}\n";
                break;
        }
        if (w.forward.enabled && w.forward.model == ForwardModel::PhaseFunction)
            o << "  forward_scatter: on\n";
        else if (w.forward.enabled)
            o << "  forward_scatter: {G: " << triple(w.forward.G.r, w.forward.G.g, w.forward.G.b)
              << ", k: " << fmt(w.forward.k) << "}\n";
        else
            o << "  forward_scatter: off\n";
    }
    if (s.snow) write_snow(o, *s.snow);
    return o.str();
}

void write_setup(const std::string& path, const Setup& setup, const std::string& comment) {
    write_text_atomically(path, comment + setup_to_yaml(setup));
}

}  // namespace deepsea
