#include "camera.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "arrays.h"
#include "convert.h"
#include "deepsea/camera/auto_exposure.h"
#include "deepsea/camera/camera_stage.h"
#include "deepsea/camera/model.h"
#include "deepsea/core/error.h"
#include "deepsea/core/hash.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/config.h"
#include "deepsea/optics/schema.h"

namespace deepsea::python {

namespace {

std::string type_name(const py::handle& h) {
    return py::str(py::type::handle_of(h).attr("__name__")).cast<std::string>();
}

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

// ---------------------------------------------------------------------------------------------
// Arguments.

/// The camera section of `config` (a setup: YAML file, YAML text, a dict {camera: ...} or a
/// list of these; or the camera section's own dict), with its camera stage.
Setup camera_setup(const py::handle& config) {
    const bool section =
        py::isinstance<py::dict>(config) && !config.cast<py::dict>().contains("camera");
    Setup s = section ? section_from(config, "camera") : setup_from(config);
    // What the messages call it: the names the YAML reader gives dicts and text.
    std::string where = section ? "<camera dict>" : "<setup dict>";
    if (is_path(config)) {
        where = path_text(config);
    } else if (py::isinstance<py::str>(config)) {
        const std::string text = config.cast<std::string>();
        where = text.find('\n') == std::string::npos ? text : "<setup text>";
    } else if (!py::isinstance<py::dict>(config)) {
        where = "config";
    }
    if (!s.camera) throw ConfigError(where + ": no camera section");
    if (!s.camera_model) {
        throw ConfigError(where +
                          ": the camera section has no camera stage: give it lens, sensor, "
                          "processing or auto_exposure keys (docs/camera.md)");
    }
    return s;
}

double number_of(const py::handle& h, const std::string& what) {
    if (!py::isinstance<py::str>(h) && !py::isinstance<py::bytes>(h) && !h.is_none()) {
        const auto f = py::reinterpret_steal<py::object>(PyNumber_Float(h.ptr()));
        if (f) return PyFloat_AsDouble(f.ptr());
        PyErr_Clear();
    }
    throw ConfigError(what + ": expected a number, got " + type_name(h));
}

/// A dict {exposure_time_ms, system_gain} (either may be left out: the sensor's) or a pair
/// (exposure_time_ms, system_gain); None: `fallback`. Ranges are the stage's (apply).
FrameExposure exposure_of(const py::handle& e, const FrameExposure& fallback) {
    FrameExposure out = fallback;
    if (e.is_none()) return out;
    if (py::isinstance<py::dict>(e)) {
        for (const auto& [k, v] : e.cast<py::dict>()) {
            const std::string key = py::str(k).cast<std::string>();
            if (key == "exposure_time_ms") {
                out.exposure_time_ms = number_of(v, "exposure.exposure_time_ms");
            } else if (key == "system_gain") {
                out.system_gain = number_of(v, "exposure.system_gain");
            } else {
                throw ConfigError("exposure: unknown key '" + key +
                                  "' (expected exposure_time_ms, system_gain)");
            }
        }
        return out;
    }
    if ((py::isinstance<py::tuple>(e) || py::isinstance<py::list>(e)) && py::len(e) == 2) {
        const py::sequence s = e.cast<py::sequence>();
        out.exposure_time_ms = number_of(s[0], "exposure.exposure_time_ms");
        out.system_gain = number_of(s[1], "exposure.system_gain");
        return out;
    }
    throw ConfigError(
        "exposure: expected a dict {exposure_time_ms, system_gain} or a pair "
        "(exposure_time_ms, system_gain), got " +
        type_name(e));
}

py::dict exposure_dict(const FrameExposure& e) {
    py::dict d;
    d["exposure_time_ms"] = e.exposure_time_ms;
    d["system_gain"] = e.system_gain;
    return d;
}

/// raw, linear_dn, noise_free: a name or an iterable of names.
CameraLayerSet layer_set_of(const py::handle& layers) {
    CameraLayerSet set;
    const auto add = [&](const py::handle& name) {
        const std::string n = py::isinstance<py::str>(name) ? name.cast<std::string>() : "";
        if (n == "raw") {
            set.raw = true;
        } else if (n == "linear_dn") {
            set.linear_dn = true;
        } else if (n == "noise_free") {
            set.noise_free = true;
        } else {
            throw ConfigError("layers: unknown layer " + py::repr(name).cast<std::string>() +
                              " (expected raw, linear_dn, noise_free)");
        }
    };
    if (py::isinstance<py::str>(layers)) {
        add(layers);
    } else if (py::isinstance<py::iterable>(layers)) {
        for (const py::handle& name : layers) add(name);
    } else {
        throw ConfigError("layers: expected names of layers (raw, linear_dn, noise_free), got " +
                          type_name(layers));
    }
    return set;
}

/// A float (H, W, 3) array of the camera's size: radiance, or the raw DN of a recorded frame.
ArrayIn inspect_float_image(const py::handle& obj, const Camera& cam, const std::string& what,
                            const char* unit) {
    const py::array a = py::array::ensure(obj);
    if (!a) throw py::error_already_set();
    const py::dtype dt = a.dtype();
    if (!(dt.kind() == 'f' && (dt.itemsize() == 4 || dt.itemsize() == 8) &&
          dt.attr("isnative").cast<bool>())) {
        throw InputError(what + ": dtype " + py::str(a.dtype()).cast<std::string>() +
                         " is not supported; give float32 or float64 " + unit);
    }
    if (a.ndim() != 3 || a.shape(0) != cam.height || a.shape(1) != cam.width || a.shape(2) != 3) {
        throw InputError(what + ": shape " + shape_text(a) + " is not the camera's (" +
                         std::to_string(cam.height) + ", " + std::to_string(cam.width) + ", 3)");
    }
    return inspect_color(a, what);
}

/// A float in a message, without Python (the GIL may be released).
std::string value_text(float v) {
    if (std::isnan(v)) return "NaN";
    if (std::isinf(v)) return v > 0.0f ? "+inf" : "-inf";
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    return text;
}

/// InputError naming the first value (row by row) that is not finite or is negative.
void require_radiance(const Image& img, const std::string& what) {
    const std::size_t n = img.data.size();
    for (std::size_t i = 0; i < n; ++i) {
        const float v = img.data[i];
        if (std::isfinite(v) && v >= 0.0f) continue;
        const std::size_t pixel = i / 3;
        throw InputError(what + ": pixel (" + std::to_string(pixel % std::size_t(img.width)) +
                         ", " + std::to_string(pixel / std::size_t(img.width)) + ") " +
                         "RGB"[i % 3] + " is " + value_text(v) +
                         ": radiance must be finite and >= 0 W/(m^2 sr)");
    }
}

// ---------------------------------------------------------------------------------------------
// The model as a dict of the config's keys (camera_config.cpp writes the same as YAML).

py::list triple(const Rgb& v) {
    py::list l;
    for (double x : {v.r, v.g, v.b}) l.append(x);
    return l;
}

py::dict settings_dict(const CameraModel& m) {
    const Lens& l = m.lens;
    py::dict lens, vignetting, distortion, sensor, processing, ae;
    vignetting["natural"] = l.vignetting.natural;
    vignetting["k1"] = l.vignetting.k1;
    vignetting["k2"] = l.vignetting.k2;
    vignetting["k3"] = l.vignetting.k3;
    distortion["k1"] = l.distortion.k1;
    distortion["k2"] = l.distortion.k2;
    distortion["p1"] = l.distortion.p1;
    distortion["p2"] = l.distortion.p2;
    distortion["k3"] = l.distortion.k3;
    lens["f_number"] = l.f_number;
    lens["transmittance"] = l.transmittance;
    lens["vignetting"] = vignetting;
    lens["distortion"] = distortion;

    const Sensor& s = m.sensor;
    sensor["pixel_pitch_um"] = s.pixel_pitch_um;
    sensor["exposure_time_ms"] = s.exposure_time_ms;
    sensor["quantum_efficiency"] = triple(s.quantum_efficiency);
    sensor["wavelength_nm"] = triple(s.wavelength_nm);
    if (s.system_gain) {
        sensor["system_gain"] = *s.system_gain;
    } else {
        sensor["iso"] = s.iso;
    }
    sensor["full_well"] = s.full_well;
    sensor["bits"] = s.bits;
    if (s.black_level) sensor["black_level"] = *s.black_level;
    sensor["dark_noise"] = s.dark_noise;
    sensor["dark_current"] = s.dark_current;
    sensor["dsnu"] = s.dsnu;
    sensor["prnu_percent"] = s.prnu_percent;
    sensor["noise"] = s.noise;
    sensor["seed"] = s.seed;

    const Processing& p = m.processing;
    if (p.white_balance == WhiteBalance::Gains) {
        py::dict gains;
        gains["gains"] = triple(p.gains);
        processing["white_balance"] = gains;
    } else {
        processing["white_balance"] = p.white_balance == WhiteBalance::None ? "none" : "grey_world";
    }
    if (p.matrix)
        processing["matrix"] = py::cast(std::vector<double>(p.matrix->begin(), p.matrix->end()));
    if (p.curve == OutputCurve::Gamma) {
        py::dict gamma;
        gamma["gamma"] = p.gamma;
        processing["curve"] = gamma;
    } else {
        processing["curve"] = p.curve == OutputCurve::Linear ? "linear" : "srgb";
    }

    const AutoExposure& a = m.auto_exposure;
    ae["enabled"] = a.enabled;
    if (a.metering == Metering::Mean) {
        ae["metering"] = "mean";
    } else {
        py::dict percentile;
        percentile["percentile"] = a.percentile;
        ae["metering"] = percentile;
    }
    ae["target"] = a.target;
    ae["damping"] = a.damping;
    ae["min_exposure_time_ms"] = a.min_exposure_time_ms;
    ae["max_exposure_time_ms"] = a.max_exposure_time_ms;
    if (a.min_system_gain) ae["min_system_gain"] = *a.min_system_gain;
    if (a.max_system_gain) ae["max_system_gain"] = *a.max_system_gain;

    py::dict d;
    d["lens"] = lens;
    d["sensor"] = sensor;
    d["processing"] = processing;
    d["auto_exposure"] = ae;
    return d;
}

// ---------------------------------------------------------------------------------------------

/// A camera stage fixed to its intrinsics. record() is safe from several Python threads at
/// once (the stage is const; each call has its own output); buffers of freed arrays come back
/// to a pool for later frames.
class PyCamera {
public:
    PyCamera(const py::object& config, int threads) : m_threads(threads) {
        check_threads(threads);
        const Setup s = camera_setup(config);
        py::gil_scoped_release nogil;
        // the port's radiance factor (docs/ports.md) where the section has one
        in_arena(threads, [&] {
            m_stage = std::make_unique<CameraStage>(*s.camera_model, *s.camera, s.port);
        });
    }

    const CameraStage& stage() const { return *m_stage; }
    const CameraModel& model() const { return m_stage->model(); }

    py::dict record(const py::object& radiance, const py::object& frame_key,
                    const py::object& exposure, const py::object& layers) const {
        const std::uint64_t key = frame_key_of(frame_key);
        const FrameExposure e = exposure_of(exposure, m_stage->default_exposure());
        CameraLayerSet set = layer_set_of(layers);
        set.raw = set.raw || model().auto_exposure.enabled;  // next_exposure meters it
        const Camera& cam = m_stage->camera();
        const ArrayIn in =
            inspect_float_image(radiance, cam, "radiance", "linear radiance, W/(m^2 sr)");
        CameraOutput out;
        {
            py::gil_scoped_release nogil;
            const int w = cam.width, h = cam.height;
            Image rad;
            reuse(rad, w, h, 3, *m_pool);
            fill_color(in, rad, m_threads, /*albedo=*/false);
            require_radiance(rad, "radiance");
            reuse(out.image, w, h, 3, *m_pool);
            if (set.raw) reuse(out.raw, w, h, 3, *m_pool);
            if (set.linear_dn) reuse(out.linear_dn, w, h, 3, *m_pool);
            if (set.noise_free) reuse(out.noise_free, w, h, 3, *m_pool);
            try {
                m_stage->apply(out, rad, key, e, set, {m_threads});
            } catch (const SchemaError& err) {
                // Name the key as the caller gave it: exposure's, not the YAML's sensor's.
                const std::string k = err.key();
                throw ConfigError("exposure." + k.substr(k.rfind('.') + 1) + ": " + err.problem());
            }
            m_pool->give(std::move(rad.data));
            // Grey world keeps the raw layer for its means: not asked for, it goes back.
            if (!set.raw && !out.raw.empty()) m_pool->give(std::move(out.raw.data));
        }
        py::dict d;
        d["image"] = to_array(std::move(out.image), m_pool);
        if (set.raw) d["raw"] = to_array(std::move(out.raw), m_pool);
        if (set.linear_dn) d["linear_dn"] = to_array(std::move(out.linear_dn), m_pool);
        if (set.noise_free) d["noise_free"] = to_array(std::move(out.noise_free), m_pool);
        d["exposure_time_ms"] = out.exposure.exposure_time_ms;
        d["system_gain"] = out.exposure.system_gain;
        const Rgb& wb = out.white_balance;
        d["white_balance"] = py::make_tuple(wb.r, wb.g, wb.b);
        d["frame_key"] = key;
        return d;
    }

    py::dict next_exposure(const py::object& recorded) const {
        if (!py::isinstance<py::dict>(recorded)) {
            throw ConfigError("recorded: expected the dict Camera.record returned, got " +
                              type_name(recorded));
        }
        const py::dict r = recorded.cast<py::dict>();
        if (!model().auto_exposure.enabled) return exposure_dict(first_exposure(model()));
        for (const char* k : {"raw", "exposure_time_ms", "system_gain"}) {
            if (!r.contains(k)) {
                throw InputError(std::string("recorded: no '") + k +
                                 "': give the dict Camera.record returned (with the controller "
                                 "on it holds the raw layer the meter reads)");
            }
        }
        CameraOutput frame;
        frame.exposure.exposure_time_ms = number_of(r["exposure_time_ms"], "exposure_time_ms");
        frame.exposure.system_gain = number_of(r["system_gain"], "system_gain");
        const ArrayIn raw =
            inspect_float_image(r["raw"], m_stage->camera(), "recorded['raw']", "DN");
        FrameExposure next;
        {
            py::gil_scoped_release nogil;
            fill_color(raw, frame.raw, m_threads, /*albedo=*/false);
            next = deepsea::next_exposure(model(), frame);
        }
        return exposure_dict(next);
    }

private:
    int m_threads = 0;
    std::unique_ptr<const CameraStage> m_stage;
    std::shared_ptr<BufferPool> m_pool = std::make_shared<BufferPool>();
};

}  // namespace

/// An int in [0, 2^64) as it is; a str hashed as `deepsea render` hashes a colour file's stem.
std::uint64_t frame_key_of(const py::handle& key) {
    if (py::isinstance<py::str>(key)) return fnv1a64(key.cast<std::string>());
    if (!py::isinstance<py::bool_>(key) && PyIndex_Check(key.ptr())) {
        const auto i = py::reinterpret_steal<py::object>(PyNumber_Index(key.ptr()));
        if (!i) throw py::error_already_set();
        const unsigned long long v = PyLong_AsUnsignedLongLong(i.ptr());
        if (!PyErr_Occurred()) return v;
        PyErr_Clear();
    }
    throw ConfigError(
        "frame_key: expected an integer from 0 to 2^64 - 1 or a str (a frame's "
        "name), got " +
        type_name(key) + " " + py::repr(key).cast<std::string>());
}

void register_camera(py::module_& m) {
    py::class_<PyCamera>(m, "Camera",
                         "A camera stage (docs/camera.md): a frame's radiance in, what a real "
                         "camera records out (lens, EMVA 1288 sensor noise, processing), and "
                         "the auto-exposure controller.")
        .def(py::init([](const py::object& config, int threads) {
                 return std::make_unique<PyCamera>(config, threads);
             }),
             py::arg("config"), py::kw_only(), py::arg("threads") = 0,
             "config: a YAML file (or text) whose camera section has lens, sensor, processing "
             "or auto_exposure keys, a dict {'camera': {...}}, or the camera section's dict. "
             "threads: worker threads (0: all cores).")
        .def_property_readonly("width", [](const PyCamera& c) { return c.stage().camera().width; })
        .def_property_readonly("height",
                               [](const PyCamera& c) { return c.stage().camera().height; })
        .def_property_readonly(
            "intrinsics", [](const PyCamera& c) { return camera_dict(c.stage().camera()); },
            "the pinhole camera (dict: width, height, fx, fy, cx, cy)")
        .def_property_readonly(
            "settings", [](const PyCamera& c) { return settings_dict(c.model()); },
            "the model as the camera section's keys (dict: lens, sensor, processing, "
            "auto_exposure), every value given; a preset's sensor values written out")
        .def_property_readonly(
            "black_level", [](const PyCamera& c) { return black_level(c.model().sensor); },
            "DN added before quantisation")
        .def_property_readonly(
            "max_dn", [](const PyCamera& c) { return max_dn(c.model().sensor); }, "2^bits - 1")
        .def("record", &PyCamera::record, py::arg("radiance"), py::arg("frame_key"), py::kw_only(),
             py::arg("exposure") = py::none(), py::arg("layers") = py::tuple(),
             "Records one frame. radiance: (H, W, 3) float32/float64 linear radiance, "
             "W/(m^2 sr) (Renderer.render's 'final'). frame_key: int, or a str hashed as "
             "`deepsea render` hashes the colour file's stem. exposure: None (the sensor's), "
             "a dict {exposure_time_ms, system_gain} or a pair. layers: any of 'raw', "
             "'linear_dn', 'noise_free' ('raw' always with auto_exposure on). Returns a dict: "
             "image (display values in [0, 1]), the layers, exposure_time_ms, system_gain, "
             "white_balance, frame_key.")
        .def(
            "first_exposure",
            [](const PyCamera& c) { return exposure_dict(first_exposure(c.model())); },
            "The first frame's settings (dict: exposure_time_ms, system_gain): the sensor's, "
            "clamped to the controller's limits when it is on.")
        .def("next_exposure", &PyCamera::next_exposure, py::arg("recorded"),
             "The next frame's settings after `recorded` (a dict record returned): the "
             "controller's damped step; the sensor's settings when it is off.")
        .def("__repr__", [](const PyCamera& c) {
            const CameraModel& mo = c.model();
            char text[160];
            std::snprintf(text, sizeof text, ", f/%g, %g ms, K %g DN/e-, %d bits%s>",
                          mo.lens.f_number, mo.sensor.exposure_time_ms, system_gain(mo.sensor),
                          mo.sensor.bits, mo.auto_exposure.enabled ? ", auto exposure" : "");
            return "<deepsea.Camera " + describe(c.stage().camera()) + text;
        });
}

}  // namespace deepsea::python
