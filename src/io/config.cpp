#include "deepsea/io/config.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include <yaml-cpp/yaml.h>

#include "deepsea/core/error.h"
#include "deepsea/optics/jerlov.h"

namespace deepsea {

namespace {

/// Scattering albedo b/c used when a config gives `attenuation` without `scattering` and no
/// preset: the mean band albedo of the six Jerlov presets (0.66; they range from 0.23 in the
/// red of clear ocean water to 0.87 in the green of turbid coastal water). A user who knows b
/// should give it; this keeps a c-only config usable with a plausible amount of backscatter.
constexpr double kDefaultAlbedo = 0.66;

// ---------------------------------------------------------------------------------------------
// Error reporting: every message is "file:line: key.path: problem".

struct Ctx {
    std::string file;
};

int line_of(const YAML::Mark& m) { return m.is_null() ? 1 : m.line + 1; }

[[noreturn]] void fail(const Ctx& ctx, const YAML::Mark& mark, const std::string& path,
                       const std::string& problem) {
    throw ConfigError(ctx.file + ":" + std::to_string(line_of(mark)) + ": " +
                      (path.empty() ? std::string("(top level)") : path) + ": " + problem);
}

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
    return out;
}

/// What a node holds, for "expected X, got Y" messages.
std::string describe(const YAML::Node& n) {
    switch (n.Type()) {
        case YAML::NodeType::Null: return "nothing";
        case YAML::NodeType::Scalar:
            return (n.Tag() == "!" ? "the string \"" : "'") + n.Scalar() +
                   (n.Tag() == "!" ? "\"" : "'");
        case YAML::NodeType::Sequence: return "a list";
        case YAML::NodeType::Map: return "a map";
        default: return "an undefined value";
    }
}

/// A value with where it came from: its key path and the best line to report.
struct Field {
    YAML::Node node;
    YAML::Mark mark;      ///< where the value starts: for errors in the value
    std::string path;
    YAML::Mark key_mark;  ///< the line of its key (or list item): for errors about the whole
                          ///< value, such as a missing key inside it
};

Field make_field(const YAML::Node& value, const YAML::Mark& key, std::string path) {
    const YAML::Mark m = value.Mark();
    // A null value ("key:" with nothing after it) may carry no mark of its own.
    return {value, m.is_null() ? key : m, std::move(path), key};
}

std::string child_path(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
}

/// The keys of one YAML map, checked against the allowed set (unknown and repeated keys are
/// errors: yaml-cpp itself silently keeps only one of two equal keys).
class MapView {
public:
    MapView(const Ctx& ctx, const Field& f, const std::vector<std::string>& allowed)
        : ctx_(ctx), field_(f) {
        if (!f.node.IsMap()) fail(ctx, f.mark, f.path, "expected a map, got " + describe(f.node));
        for (auto it = f.node.begin(); it != f.node.end(); ++it) {
            const YAML::Node k = it->first;  // a copy: it-> yields a temporary
            const std::string path = child_path(f.path, k.IsScalar() ? k.Scalar() : "?");
            if (!k.IsScalar()) fail(ctx, k.Mark(), f.path, "keys must be plain names");
            const std::string key = k.Scalar();
            if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
                fail(ctx, k.Mark(), path,
                     "unknown key (expected " + join(allowed, ", ") + ")");
            if (entries_.count(key))
                fail(ctx, k.Mark(), path,
                     "repeated key (first given on line " +
                         std::to_string(line_of(entries_.at(key).mark)) + ")");
            entries_.emplace(key, make_field(it->second, k.Mark(), path));
        }
    }

    bool has(const std::string& key) const { return entries_.count(key) != 0; }
    const Field& mark_field() const { return field_; }

    /// A required key: missing is reported at the line of the enclosing map's key.
    const Field& need(const std::string& key) const {
        const auto it = entries_.find(key);
        if (it == entries_.end())
            fail(ctx_, field_.key_mark.is_null() ? field_.mark : field_.key_mark,
                 child_path(field_.path, key), "missing required key");
        return it->second;
    }
    const Field* opt(const std::string& key) const {
        const auto it = entries_.find(key);
        return it == entries_.end() ? nullptr : &it->second;
    }
    std::vector<std::string> keys() const {
        std::vector<std::string> k;
        for (const auto& e : entries_) k.push_back(e.first);
        return k;
    }

private:
    const Ctx& ctx_;
    Field field_;
    std::map<std::string, Field> entries_;
};

// ---------------------------------------------------------------------------------------------
// Scalars and vectors.

/// Shortest text that reads back to exactly v (messages and setup_to_yaml).
std::string fmt(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

double get_number(const Ctx& ctx, const Field& f) {
    // A quoted scalar ("1.0") is a string in YAML: strict configs do not coerce it.
    if (!f.node.IsScalar() || f.node.Tag() == "!")
        fail(ctx, f.mark, f.path, "expected a number, got " + describe(f.node));
    double v = 0.0;
    try {
        v = f.node.as<double>();
    } catch (const YAML::Exception&) {
        fail(ctx, f.mark, f.path, "expected a number, got " + describe(f.node));
    }
    if (!std::isfinite(v)) fail(ctx, f.mark, f.path, "must be a finite number");
    return v;
}

int get_int(const Ctx& ctx, const Field& f) {
    if (!f.node.IsScalar() || f.node.Tag() == "!")
        fail(ctx, f.mark, f.path, "expected an integer, got " + describe(f.node));
    long long v = 0;
    try {
        v = f.node.as<long long>();
    } catch (const YAML::Exception&) {
        fail(ctx, f.mark, f.path, "expected an integer, got " + describe(f.node));
    }
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
        fail(ctx, f.mark, f.path, "integer out of range");
    return int(v);
}

std::string get_string(const Ctx& ctx, const Field& f) {
    if (!f.node.IsScalar()) fail(ctx, f.mark, f.path, "expected a string, got " + describe(f.node));
    return f.node.Scalar();
}

std::vector<Field> get_list(const Ctx& ctx, const Field& f) {
    if (!f.node.IsSequence())
        fail(ctx, f.mark, f.path, "expected a list, got " + describe(f.node));
    std::vector<Field> out;
    for (std::size_t i = 0; i < f.node.size(); ++i)
        out.push_back(make_field(f.node[i], f.node[i].Mark().is_null() ? f.mark : f.node[i].Mark(),
                                 f.path + "[" + std::to_string(i) + "]"));
    return out;
}

std::array<double, 3> get_triple(const Ctx& ctx, const Field& f, const char* what) {
    const auto items = get_list(ctx, f);
    if (items.size() != 3)
        fail(ctx, f.mark, f.path,
             std::string("expected a list of 3 numbers [") + what + "], got " +
                 std::to_string(items.size()));
    return {get_number(ctx, items[0]), get_number(ctx, items[1]), get_number(ctx, items[2])};
}

Vec3 get_vec3(const Ctx& ctx, const Field& f) {
    const auto v = get_triple(ctx, f, "x, y, z");
    return {v[0], v[1], v[2]};
}

/// R, G, B triple with each channel >= 0.
Rgb get_rgb(const Ctx& ctx, const Field& f) {
    const auto v = get_triple(ctx, f, "r, g, b");
    static const char* names[] = {"R", "G", "B"};
    for (int i = 0; i < 3; ++i)
        if (v[i] < 0.0)
            fail(ctx, f.mark, f.path,
                 std::string("must be >= 0 (") + names[i] + " is " + fmt(v[i]) + ")");
    return {v[0], v[1], v[2]};
}

// ---------------------------------------------------------------------------------------------
// camera
//
//   key     unit    range     required
//   width   pixels  int > 0   yes
//   height  pixels  int > 0   yes
//   fx, fy  pixels  > 0       yes
//   cx, cy  pixels  any       yes   (pixel centres at integer coordinates, DESIGN.md 1)

Camera parse_camera(const Ctx& ctx, const Field& f) {
    const MapView m(ctx, f, {"width", "height", "fx", "fy", "cx", "cy"});
    Camera cam;
    auto positive_int = [&](const char* key) {
        const Field& v = m.need(key);
        const int x = get_int(ctx, v);
        if (x <= 0) fail(ctx, v.mark, v.path, "must be > 0, got " + std::to_string(x));
        return x;
    };
    auto positive = [&](const char* key) {
        const Field& v = m.need(key);
        const double x = get_number(ctx, v);
        if (x <= 0.0) fail(ctx, v.mark, v.path, "must be > 0, got " + fmt(x));
        return x;
    };
    cam.width = positive_int("width");
    cam.height = positive_int("height");
    cam.fx = positive("fx");
    cam.fy = positive("fy");
    cam.cx = get_number(ctx, m.need("cx"));
    cam.cy = get_number(ctx, m.need("cy"));
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

Rid parse_rid(const Ctx& ctx, const Field& f) {
    const MapView m(ctx, f, {"gaussian", "table"});
    if (m.has("gaussian") == m.has("table"))
        fail(ctx, f.mark, f.path, "give exactly one of gaussian, table");
    Rid rid;
    if (const Field* g = m.opt("gaussian")) {
        const MapView gm(ctx, *g, {"sigma_deg"});
        const Field& s = gm.need("sigma_deg");
        rid.kind = Rid::Kind::Gaussian;
        rid.sigma_deg = get_number(ctx, s);
        if (rid.sigma_deg <= 0.0) fail(ctx, s.mark, s.path, "must be > 0 degrees");
        return rid;
    }
    const Field& t = *m.opt("table");
    const MapView tm(ctx, t, {"angle_deg", "value"});
    const Field& af = tm.need("angle_deg");
    const Field& vf = tm.need("value");
    rid.kind = Rid::Kind::Table;
    for (const Field& a : get_list(ctx, af)) {
        const double x = get_number(ctx, a);
        if (x < 0.0 || x > 180.0) fail(ctx, a.mark, a.path, "must be in [0, 180] degrees");
        if (!rid.angle_deg.empty() && x <= rid.angle_deg.back())
            fail(ctx, a.mark, a.path, "angles must be strictly ascending");
        rid.angle_deg.push_back(x);
    }
    for (const Field& v : get_list(ctx, vf)) {
        const double x = get_number(ctx, v);
        if (x < 0.0) fail(ctx, v.mark, v.path, "must be >= 0");
        rid.value.push_back(x);
    }
    if (rid.angle_deg.size() < 2) fail(ctx, af.mark, af.path, "needs at least 2 angles");
    if (rid.value.size() != rid.angle_deg.size())
        fail(ctx, vf.mark, vf.path,
             "has " + std::to_string(rid.value.size()) + " values for " +
                 std::to_string(rid.angle_deg.size()) + " angles");
    return rid;
}

Light parse_light(const Ctx& ctx, const Field& f, std::size_t index) {
    const MapView m(ctx, f, {"name", "position", "direction", "intensity", "rid", "cutoff_deg"});
    Light l;
    l.name = m.has("name") ? get_string(ctx, *m.opt("name")) : "light" + std::to_string(index + 1);
    l.position = get_vec3(ctx, m.need("position"));
    const Field& d = m.need("direction");
    const Vec3 dir = get_vec3(ctx, d);
    if (!(length(dir) > 1e-12)) fail(ctx, d.mark, d.path, "must not be the zero vector");
    l.direction = normalize(dir);
    l.intensity = get_rgb(ctx, m.need("intensity"));
    if (const Field* r = m.opt("rid")) l.rid = parse_rid(ctx, *r);
    if (const Field* c = m.opt("cutoff_deg")) {
        const double x = get_number(ctx, *c);
        if (x <= 0.0 || x > 180.0) fail(ctx, c->mark, c->path, "must be in (0, 180] degrees");
        l.rid.cutoff_deg = x;
    }
    return l;
}

Rig parse_rig(const Ctx& ctx, const Field& f) {
    const MapView m(ctx, f, {"name", "lights"});
    Rig rig;
    if (const Field* n = m.opt("name")) rig.name = get_string(ctx, *n);
    const Field& lf = m.need("lights");
    const auto items = get_list(ctx, lf);
    if (items.empty()) fail(ctx, lf.mark, lf.path, "needs at least one light");
    std::map<std::string, int> seen;
    for (std::size_t i = 0; i < items.size(); ++i) {
        Light l = parse_light(ctx, items[i], i);
        if (seen.count(l.name))
            fail(ctx, items[i].mark, items[i].path,
                 "light name '" + l.name + "' already used by lights[" +
                     std::to_string(seen[l.name]) + "]");
        seen[l.name] = int(i);
        rig.lights.push_back(std::move(l));
    }
    return rig;
}

// ---------------------------------------------------------------------------------------------
// water
//
//   key              unit   range                               default
//   name             -      string                              the preset's, else "custom"
//   preset           -      jerlov:<IB|II|III|1C|3C|5C>         none
//   attenuation      1/m    [r, g, b], each >= 0 (c)            the preset's; required without
//   scattering       1/m    [r, g, b], 0 <= b <= c per channel  the preset's albedo b/c times c,
//                                                               else 0.66 c (kDefaultAlbedo)
//   phase            -      isotropic | {petzold: clear|coastal|turbid}
//                           | {henyey_greenstein: {g: (-1, 1)}} the preset's, else petzold clear
//   forward_scatter  -      off | on | {G: [r, g, b] 1/m, 0 <= G <= c; k: rad/m >= 0}    off
//                           (on: default_forward_scatter of the final c, b and phase)

Phase parse_phase(const Ctx& ctx, const Field& f) {
    Phase p;
    if (f.node.IsScalar()) {
        // The names of to_string(PhaseKind) are accepted as plain scalars as well.
        const std::string s = f.node.Scalar();
        if (s == "isotropic") p.kind = PhaseKind::Isotropic;
        else if (s == "petzold:clear") p.kind = PhaseKind::PetzoldClear;
        else if (s == "petzold:coastal") p.kind = PhaseKind::PetzoldCoastal;
        else if (s == "petzold:turbid") p.kind = PhaseKind::PetzoldTurbid;
        else
            fail(ctx, f.mark, f.path,
                 "unknown phase function '" + s +
                     "' (expected isotropic, {petzold: clear|coastal|turbid} or "
                     "{henyey_greenstein: {g: ..}})");
        return p;
    }
    const MapView m(ctx, f, {"petzold", "henyey_greenstein"});
    if (m.has("petzold") == m.has("henyey_greenstein"))
        fail(ctx, f.mark, f.path, "give exactly one of petzold, henyey_greenstein");
    if (const Field* pz = m.opt("petzold")) {
        const std::string s = get_string(ctx, *pz);
        if (s == "clear") p.kind = PhaseKind::PetzoldClear;
        else if (s == "coastal") p.kind = PhaseKind::PetzoldCoastal;
        else if (s == "turbid") p.kind = PhaseKind::PetzoldTurbid;
        else fail(ctx, pz->mark, pz->path, "expected clear, coastal or turbid, got '" + s + "'");
        return p;
    }
    const MapView hg(ctx, *m.opt("henyey_greenstein"), {"g"});
    const Field& g = hg.need("g");
    p.kind = PhaseKind::HenyeyGreenstein;
    p.g = get_number(ctx, g);
    if (!(p.g > -1.0 && p.g < 1.0)) fail(ctx, g.mark, g.path, "must be in (-1, 1)");
    return p;
}

Water parse_water(const Ctx& ctx, const Field& f) {
    const MapView m(ctx, f, {"name", "preset", "attenuation", "scattering", "phase",
                             "forward_scatter"});
    Water w;
    w.name = "custom";
    w.phase.kind = PhaseKind::PetzoldClear;
    const Field* preset = m.opt("preset");
    if (preset) {
        const std::string s = get_string(ctx, *preset);
        const std::string prefix = "jerlov:";
        if (s.compare(0, prefix.size(), prefix) != 0)
            fail(ctx, preset->mark, preset->path, "expected jerlov:<TYPE>, got '" + s + "'");
        try {
            w = jerlov_water(s.substr(prefix.size()));
        } catch (const ConfigError& e) {
            fail(ctx, preset->mark, preset->path, e.what());
        }
    }
    const Rgb preset_c = w.c, preset_b = w.b;
    const Field* att = m.opt("attenuation");
    if (att) w.c = get_rgb(ctx, *att);
    else if (!preset) m.need("attenuation");  // throws: required without a preset

    const Field* sca = m.opt("scattering");
    if (sca) {
        w.b = get_rgb(ctx, *sca);
    } else if (!preset) {
        w.b = w.c * kDefaultAlbedo;
    } else if (att) {
        // New c on a preset: keep the preset's single-scattering albedo b/c per channel.
        for (int i = 0; i < 3; ++i)
            w.b[i] = preset_c[i] > 0.0 ? w.c[i] * preset_b[i] / preset_c[i] : 0.0;
    }
    static const char* names[] = {"R", "G", "B"};
    for (int i = 0; i < 3; ++i) {
        if (w.b[i] > w.c[i]) {
            const Field& where = sca ? *sca : (att ? *att : *preset);
            fail(ctx, where.mark, sca ? where.path : child_path(f.path, "scattering"),
                 std::string("scattering must not exceed attenuation (") + names[i] + ": b = " +
                     fmt(w.b[i]) + " > c = " + fmt(w.c[i]) + ")");
        }
    }
    if (const Field* ph = m.opt("phase")) w.phase = parse_phase(ctx, *ph);
    if (const Field* n = m.opt("name")) w.name = get_string(ctx, *n);

    if (const Field* fw = m.opt("forward_scatter")) {
        if (fw->node.IsScalar()) {
            const std::string s = fw->node.Scalar();
            if (s == "off" || s == "false") {
                w.forward = ForwardScatter{};
            } else if (s == "on" || s == "true") {
                w.forward = default_forward_scatter(w);
            } else {
                fail(ctx, fw->mark, fw->path,
                     "expected off, on or {G: [r, g, b], k: ..}, got '" + s + "'");
            }
        } else {
            const MapView fm(ctx, *fw, {"G", "k"});
            const Field& gf = fm.need("G");
            const Field& kf = fm.need("k");
            ForwardScatter fs;
            fs.enabled = true;
            fs.G = get_rgb(ctx, gf);
            for (int i = 0; i < 3; ++i)
                if (fs.G[i] > w.c[i])
                    fail(ctx, gf.mark, gf.path,
                         std::string("G must not exceed attenuation c (") + names[i] +
                             ": G = " + fmt(fs.G[i]) + " > c = " + fmt(w.c[i]) + ")");
            fs.k = get_number(ctx, kf);
            if (fs.k < 0.0) fail(ctx, kf.mark, kf.path, "must be >= 0 rad/m");
            w.forward = fs;
        }
    }
    return w;
}

// ---------------------------------------------------------------------------------------------
// Documents and files.

struct Parsed {
    Setup setup;
    std::map<std::string, int> line;  ///< line of each section found
};

Parsed parse_document(const std::string& text, const std::string& file) {
    const Ctx ctx{file};
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
        throw ConfigError(file + ":" + std::to_string(line_of(e.mark)) +
                          ": YAML syntax error: " + e.msg);
    }
    Parsed out;
    try {
        if (root.IsNull())
            fail(ctx, YAML::Mark::null_mark(), "",
                 "empty configuration (expected camera, rig and/or water sections)");
        const Field top{root, root.Mark(), "", root.Mark()};
        const MapView m(ctx, top, {"camera", "rig", "water"});
        if (const Field* c = m.opt("camera")) {
            out.setup.camera = parse_camera(ctx, *c);
            out.line["camera"] = line_of(c->key_mark);
        }
        if (const Field* r = m.opt("rig")) {
            out.setup.rig = parse_rig(ctx, *r);
            out.line["rig"] = line_of(r->key_mark);
        }
        if (const Field* w = m.opt("water")) {
            out.setup.water = parse_water(ctx, *w);
            out.line["water"] = line_of(w->key_mark);
        }
    } catch (const YAML::Exception& e) {
        // Should not happen after the checks above; keep the one-line file:line format anyway.
        throw ConfigError(file + ":" + std::to_string(line_of(e.mark)) + ": " + e.msg);
    }
    return out;
}

std::string read_text(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw IoError(path + ": no such file");
    if (std::filesystem::is_directory(path, ec))
        throw IoError(path + ": is a folder, not a config file");
    std::ifstream is(path, std::ios::binary);
    if (!is) throw IoError(path + ": cannot read: " + std::strerror(errno));
    std::ostringstream ss;
    ss << is.rdbuf();
    if (is.bad()) throw IoError(path + ": read error");
    return ss.str();
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
    return parse_document(yaml_text, file_name).setup;
}

Setup load_setup(const std::vector<std::string>& files) {
    Setup all;
    std::map<std::string, std::string> where;  // section -> "file:line" of its first definition
    for (const auto& file : files) {
        Parsed p = parse_document(read_text(file), file);
        auto merge = [&](auto& dst, auto& src, const char* name) {
            if (!src) return;
            const std::string here = file + ":" + std::to_string(p.line[name]);
            if (dst)
                throw ConfigError(here + ": " + name + ": section given twice (first in " +
                                  where[name] + ")");
            dst = std::move(src);
            where[name] = here;
        };
        merge(all.camera, p.setup.camera, "camera");
        merge(all.rig, p.setup.rig, "rig");
        merge(all.water, p.setup.water, "water");
    }
    return all;
}

Water load_water(const std::string& spec) {
    const std::string prefix = "jerlov:";
    if (spec.compare(0, prefix.size(), prefix) == 0) {
        try {
            return jerlov_water(spec.substr(prefix.size()));
        } catch (const ConfigError& e) {
            throw ConfigError(spec + ": " + e.what());
        }
    }
    Parsed p = parse_document(read_text(spec), spec);
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
    }
    if (s.rig) {
        o << "rig:\n";
        if (!s.rig->name.empty()) o << "  name: " << quote(s.rig->name) << "\n";
        o << "  lights:\n";
        for (const Light& l : s.rig->lights) {
            o << "    - name: " << quote(l.name) << "\n"
              << "      position: " << triple(l.position.x, l.position.y, l.position.z) << "\n"
              << "      direction: " << triple(l.direction.x, l.direction.y, l.direction.z)
              << "\n"
              << "      intensity: " << triple(l.intensity.r, l.intensity.g, l.intensity.b)
              << "\n";
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
            case PhaseKind::Isotropic: o << "isotropic\n"; break;
            case PhaseKind::HenyeyGreenstein:
                o << "{henyey_greenstein: {g: " << fmt(w.phase.g) << "}}\n";
                break;
            case PhaseKind::PetzoldClear: o << "{petzold: clear}\n"; break;
            case PhaseKind::PetzoldCoastal: o << "{petzold: coastal}\n"; break;
            case PhaseKind::PetzoldTurbid: o << "{petzold: turbid}\n"; break;
        }
        if (w.forward.enabled)
            o << "  forward_scatter: {G: " << triple(w.forward.G.r, w.forward.G.g, w.forward.G.b)
              << ", k: " << fmt(w.forward.k) << "}\n";
        else
            o << "  forward_scatter: off\n";
    }
    return o.str();
}

}  // namespace deepsea
