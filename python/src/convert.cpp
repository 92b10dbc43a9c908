#include "convert.h"

#include <algorithm>
#include <string>

#include "deepsea/batch/snow_setup.h"
#include "deepsea/core/error.h"

namespace deepsea::python {

namespace {

py::object json_module() { return py::module_::import("json"); }

}  // namespace

/// JSON text of a Python value; NumPy scalars and arrays become numbers and lists.
std::string to_json(const py::handle& value) {
    const py::object tolist = py::cpp_function([](const py::object& o) -> py::object {
        if (py::hasattr(o, "tolist")) return o.attr("tolist")();
        throw py::type_error("setup: cannot use a " +
                             py::str(py::type::handle_of(o).attr("__name__")).cast<std::string>() +
                             " as a setting");
    });
    return json_module()
        .attr("dumps")(value, py::arg("indent") = 1, py::arg("default") = tolist)
        .cast<std::string>();
}

py::object json_loads(const std::string& text) { return json_module().attr("loads")(text); }

bool is_path(const py::handle& h) {
    return py::isinstance(h, py::module_::import("os").attr("PathLike"));
}

/// A str or os.PathLike as a path (TypeError from os.fspath otherwise). A NUL character is a
/// ConfigError (a ValueError, as Python's own file functions raise): the C library would end
/// the name there and open another file.
std::string path_text(const py::handle& h) {
    std::string path = py::module_::import("os").attr("fspath")(h).cast<std::string>();
    if (path.find('\0') != std::string::npos) {
        throw ConfigError(path.substr(0, path.find('\0')) +
                          "...: the file name holds a NUL character");
    }
    return path;
}

namespace {

/// Adds `more`'s sections to `into`; a section given twice is an error.
void merge(Setup& into, const Setup& more, const std::string& where) {
    const auto take = [&](auto& dst, const auto& src, const char* name) {
        if (!src) return;
        if (dst) throw ConfigError(where + ": " + name + " given twice");
        dst = src;
    };
    take(into.camera, more.camera, "camera");
    if (more.camera) {  // the camera section's stage and port
        into.camera_model = more.camera_model;
        into.port = more.port;
    }
    take(into.rig, more.rig, "rig");
    take(into.water, more.water, "water");
}

}  // namespace

/// One part of a setup: None, a dict {camera, rig, water}, YAML text (a str with a line break),
/// a file path (str or os.PathLike), or a list of these.
Setup setup_from(const py::handle& obj) {
    Setup s;
    if (obj.is_none()) return s;
    if (py::isinstance<py::dict>(obj)) return parse_setup(to_json(obj), "<setup dict>");
    if (is_path(obj)) return load_setup({path_text(obj)});
    if (py::isinstance<py::str>(obj)) {
        const std::string text = obj.cast<std::string>();
        if (text.find('\n') != std::string::npos) return parse_setup(text, "<setup text>");
        return load_setup({text});
    }
    if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
        for (const py::handle& part : obj) merge(s, setup_from(part), "setup");
        return s;
    }
    throw ConfigError("setup: expected YAML text, a file path, a dict or a list of them, got " +
                      py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>());
}

/// One section given on its own (camera=, rig=, water=): its dict (the section's content),
/// YAML text or a file holding that section, or for water a preset name ("jerlov:IB").
Setup section_from(const py::handle& obj, const char* name) {
    if (obj.is_none()) return {};
    if (py::isinstance<py::dict>(obj)) {
        py::dict wrapped;
        wrapped[name] = obj;
        return parse_setup(to_json(wrapped), std::string("<") + name + " dict>");
    }
    if (std::string(name) == "water" && py::isinstance<py::str>(obj)) {
        const std::string spec = obj.cast<std::string>();
        if (spec.find('\n') == std::string::npos) {
            Setup s;
            s.water = load_water(spec);  // a preset, or a file with a water section
            return s;
        }
    }
    Setup s = setup_from(obj);
    const bool has = std::string(name) == "camera" ? bool(s.camera)
                     : std::string(name) == "rig"  ? bool(s.rig)
                                                   : bool(s.water);
    if (!has) throw ConfigError(std::string(name) + "=: no " + name + " section");
    return s;
}

Setup full_setup(const py::handle& setup, const py::handle& camera, const py::handle& rig,
                 const py::handle& water) {
    Setup s = setup_from(setup);
    merge(s, section_from(camera, "camera"), "camera=");
    merge(s, section_from(rig, "rig"), "rig=");
    merge(s, section_from(water, "water"), "water=");
    return s;
}

py::dict camera_dict(const Camera& c) {
    py::dict d;
    d["width"] = c.width;
    d["height"] = c.height;
    d["fx"] = c.fx;
    d["fy"] = c.fy;
    d["cx"] = c.cx;
    d["cy"] = c.cy;
    return d;
}

DepthKind parse_depth_kind(const std::string& kind) {
    if (kind == "z") return DepthKind::Z;
    if (kind == "range") return DepthKind::Range;
    throw ConfigError("depth_kind: expected 'z' (planar) or 'range' (along the ray), got '" + kind +
                      "'");
}

void check_depth_scale(double scale) {
    if (!(scale > 0.0)) {
        throw ConfigError("depth_scale: must be > 0 metres per unit, got " + std::to_string(scale));
    }
}

std::optional<SnowSettings> snow_of(const py::handle& snow, std::uint64_t seed,
                                    const std::optional<CameraModel>& model) {
    if (snow.is_none()) return std::nullopt;
    if (!py::isinstance<py::str>(snow) && !py::isinstance<py::dict>(snow))
        throw ConfigError("snow: expected a preset's name, 'off' or a dict, got " +
                          py::repr(snow).cast<std::string>());
    py::dict wrapped;
    wrapped["snow"] = snow;
    const Setup s = parse_setup(to_json(wrapped), "<snow=>");
    if (!s.snow) return std::nullopt;  // "off"
    return make_snow_settings(*s.snow, seed, model);
}

std::optional<CameraPose> pose_of(const py::handle& pose) {
    if (pose.is_none()) return std::nullopt;
    const auto bad = [&](const std::string& why) {
        return ConfigError("pose: " + why + " (a 4x4 or 3x4 camera-to-world matrix)");
    };
    py::array_t<double, py::array::c_style | py::array::forcecast> a;
    try {
        a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(pose);
    } catch (const py::error_already_set&) {
    }
    if (!a || a.ndim() != 2 || a.shape(1) != 4 || (a.shape(0) != 3 && a.shape(0) != 4))
        throw bad("expected a 4x4 or 3x4 array of numbers");
    const auto m = a.unchecked<2>();
    for (py::ssize_t r = 0; r < a.shape(0); ++r)
        for (py::ssize_t c = 0; c < 4; ++c)
            if (!std::isfinite(m(r, c))) throw bad("not finite");
    const auto column = [&](int c) { return Vec3{m(0, c), m(1, c), m(2, c)}; };
    CameraPose p{column(3), column(0), column(1), column(2)};
    const Vec3 axes[3] = {p.right, p.down, p.forward};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (std::fabs(dot(axes[i], axes[j]) - (i == j ? 1.0 : 0.0)) > 1e-6)
                throw bad("its 3x3 part is not a rotation");
    if (std::fabs(dot(cross(p.right, p.down), p.forward) - 1.0) > 1e-6)
        throw bad("its 3x3 part is a reflection, not a rotation");
    return p;
}

std::optional<Shutter> shutter_of(const py::handle& shutter) {
    if (shutter.is_none()) return std::nullopt;
    if (!py::isinstance<py::sequence>(shutter) || py::isinstance<py::str>(shutter) ||
        py::len(shutter) != 2)
        throw ConfigError("shutter: expected a pair (open, close) of camera-to-world matrices");
    const py::sequence s = py::reinterpret_borrow<py::sequence>(shutter);
    try {
        return Shutter{*pose_of(s[0]), *pose_of(s[1])};
    } catch (const ConfigError& e) {
        throw ConfigError(std::string("shutter: ") + e.what());
    } catch (const std::bad_optional_access&) {
        throw ConfigError("shutter: a pose is None");
    }
}

LayerOutput parse_layers(const py::handle& layers) {
    std::string list;
    if (py::isinstance<py::str>(layers)) {
        list = layers.cast<std::string>();
    } else if (py::isinstance<py::list>(layers) || py::isinstance<py::tuple>(layers)) {
        for (const py::handle& name : layers) {
            if (!py::isinstance<py::str>(name))
                throw ConfigError("layers: expected layer names, got " +
                                  py::repr(name).cast<std::string>());
            list += (list.empty() ? "" : ",") + name.cast<std::string>();
        }
    } else {
        throw ConfigError(
            "layers: expected 'all', names such as 'final,depth', or a list of "
            "names, got " +
            py::repr(layers).cast<std::string>());
    }
    LayerOutput out;
    try {
        out.names = parse_layer_set(list);
    } catch (const ConfigError& e) {
        const std::string m = e.what(), cli = "--layer-set: ";  // the CLI's option; here layers=
        throw ConfigError("layers: " + (m.rfind(cli, 0) == 0 ? m.substr(cli.size()) : m));
    }
    return out;
}

py::dict layers_dict(Layers& l, const std::shared_ptr<BufferPool>& pool,
                     const LayerOutput* wanted) {
    py::dict d;
    const auto put = [&](const char* name, Image& img) {
        if (img.empty()) return;
        const bool named =
            !wanted || wanted->all() ||
            std::find(wanted->names.begin(), wanted->names.end(), name) != wanted->names.end();
        if (named) {
            d[name] = to_array(std::move(img), pool);
        } else if (pool) {
            pool->give(std::move(img.data));  // computed, not wanted: kept for the next frame
        }
    };
    put("final", l.final);
    put("direct", l.direct);
    put("forward", l.forward);
    put("backscatter", l.backscatter);
    put("transmission", l.transmission);
    put("depth", l.depth);
    put("normal", l.normal);
    put("mask", l.mask);  // through a port only
    put("snow", l.snow);  // with marine snow only
    put("snow_id", l.snow_id);
    return d;
}

}  // namespace deepsea::python
