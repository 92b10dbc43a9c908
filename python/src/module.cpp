// The `deepsea` Python module (docs/python.md): assets, frames rendered from NumPy arrays into
// NumPy layers, bakes, asset info and the reference renderer. A thin layer over the public
// libraries, like the CLI: it converts arrays and arguments, calls one library function with
// the GIL released, and turns deepsea's exceptions into Python ones with the same message.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <string>

#include "arrays.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/config.h"
#include "deepsea/reference/reference.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/renderer.h"

namespace deepsea::python {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// ---------------------------------------------------------------------------------------------
// Exceptions: deepsea.Error and one subclass per library type, each also a subclass of the
// built-in exception a Python user would catch for it. The message is the CLI's line.

struct ErrorTypes {
    PyObject* error = nullptr;
    PyObject* config = nullptr;
    PyObject* input = nullptr;
    PyObject* io = nullptr;
    PyObject* asset = nullptr;
    PyObject* accuracy = nullptr;
    PyObject* cancelled = nullptr;
    PyObject* memory = nullptr;
};
ErrorTypes g_errors;  // owned by the module (its attributes); never freed

PyObject* add_error(py::module_& m, const char* name, PyObject* base, PyObject* builtin,
                    const char* doc) {
    const std::string qualified = std::string("deepsea.") + name;
    py::object bases = builtin ? py::object(py::make_tuple(py::handle(base), py::handle(builtin)))
                               : py::object(py::reinterpret_borrow<py::object>(base));
    PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
    if (!type) throw py::error_already_set();
    m.add_object(name, py::handle(type));  // the module keeps a reference; so do we
    return type;
}

void register_errors(py::module_& m) {
    g_errors.error = add_error(m, "Error", PyExc_Exception, nullptr,
                               "Base of every deepsea error; str() is the CLI's one line.");
    g_errors.config = add_error(m, "ConfigError", g_errors.error, PyExc_ValueError,
                                "A setting is unknown, missing, of the wrong type or out of "
                                "range (the message names the file, line and key).");
    g_errors.input = add_error(m, "InputError", g_errors.error, PyExc_ValueError,
                               "Input data is unusable: dtype, shape, sizes that differ.");
    g_errors.io =
        add_error(m, "IoError", g_errors.error, PyExc_OSError, "A file cannot be read or written.");
    g_errors.asset = add_error(m, "AssetError", g_errors.error, PyExc_ValueError,
                               "An asset is foreign, truncated, of an unknown format, or made "
                               "for another camera.");
    g_errors.accuracy = add_error(m, "AccuracyError", g_errors.error, PyExc_RuntimeError,
                                  "A strict bake check missed the accuracy bar.");
    g_errors.cancelled = add_error(m, "Cancelled", g_errors.error, PyExc_RuntimeError,
                                   "A long operation was stopped.");
    g_errors.memory = add_error(m, "OutOfMemoryError", g_errors.error, PyExc_MemoryError,
                                "The work needs more memory than the machine has left.");
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const std::bad_alloc&) {
            PyErr_SetString(g_errors.memory,
                            "out of memory (the inputs or settings need more "
                            "memory than this machine has left)");
        } catch (const std::filesystem::filesystem_error& e) {
            const std::string path = e.path1().empty() ? "a path" : e.path1().string();
            PyErr_SetString(g_errors.io, one_line(path + ": " + e.code().message(), 1000).c_str());
        } catch (const OutOfMemory& e) {
            PyErr_SetString(g_errors.memory, one_line(e.what(), 1000).c_str());
        } catch (const ConfigError& e) {
            PyErr_SetString(g_errors.config, one_line(e.what(), 1000).c_str());
        } catch (const InputError& e) {
            PyErr_SetString(g_errors.input, one_line(e.what(), 1000).c_str());
        } catch (const IoError& e) {
            PyErr_SetString(g_errors.io, one_line(e.what(), 1000).c_str());
        } catch (const AssetError& e) {
            PyErr_SetString(g_errors.asset, one_line(e.what(), 1000).c_str());
        } catch (const AccuracyError& e) {
            PyErr_SetString(g_errors.accuracy, one_line(e.what(), 1000).c_str());
        } catch (const Cancelled& e) {
            PyErr_SetString(g_errors.cancelled, one_line(e.what(), 1000).c_str());
        } catch (const Error& e) {
            PyErr_SetString(g_errors.error, one_line(e.what(), 1000).c_str());
        }
    });
}

// ---------------------------------------------------------------------------------------------
// Setups: YAML text, a YAML file, or Python dicts (given to the strict YAML reader as JSON,
// which is YAML), or a list of those; sections merge as `deepsea bake --config a --config b`.

py::object json_module() { return py::module_::import("json"); }

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

/// Adds `more`'s sections to `into`; a section given twice is an error.
void merge(Setup& into, const Setup& more, const std::string& where) {
    const auto take = [&](auto& dst, const auto& src, const char* name) {
        if (!src) return;
        if (dst) throw ConfigError(where + ": " + name + " given twice");
        dst = src;
    };
    take(into.camera, more.camera, "camera");
    take(into.rig, more.rig, "rig");
    take(into.water, more.water, "water");
}

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

/// Layers as a dict of arrays (moved out: no copy; their buffers return to `pool`, if given,
/// when the arrays are freed); empty layers are left out.
py::dict layers_dict(Layers& l, const std::shared_ptr<BufferPool>& pool = {}) {
    py::dict d;
    const auto put = [&](const char* name, Image& img) {
        if (!img.empty()) d[name] = to_array(std::move(img), pool);
    };
    put("final", l.final);
    put("direct", l.direct);
    put("forward", l.forward);
    put("backscatter", l.backscatter);
    put("transmission", l.transmission);
    put("depth", l.depth);
    put("normal", l.normal);
    return d;
}

// ---------------------------------------------------------------------------------------------
// Assets and rendering.

/// A loaded (or baked) asset, shared by the renderers made from it.
struct PyAsset {
    std::shared_ptr<const Asset> asset;
    std::string path;  ///< file it was loaded from or written to; empty for a bake in memory
};

PyAsset load(const py::object& file, int threads) {
    check_threads(threads);
    const std::string path = path_text(file);
    auto a = std::make_shared<Asset>();
    {
        py::gil_scoped_release nogil;
        in_arena(threads, [&] { *a = load_asset(path); });
    }
    return {std::move(a), path};
}

py::object json_loads(const std::string& text) { return json_module().attr("loads")(text); }

/// Composites frames of one asset, keeping its scratch buffers between frames of one size.
/// One frame at a time (a lock); Python threads may share it, or use one renderer each to
/// render in parallel.
class PyRenderer {
public:
    PyRenderer(PyAsset asset, const py::handle& camera, bool forward, int threads)
        : m_asset(std::move(asset)), m_threads(threads) {
        check_threads(threads);
        RenderSettings settings;
        if (!camera.is_none()) settings.camera = *section_from(camera, "camera").camera;
        settings.forward = forward;
        m_renderer = std::make_unique<deepsea::Renderer>(*m_asset.asset, settings);
    }

    py::dict render(const py::object& rgb, const py::object& depth, const std::string& depth_kind,
                    double depth_scale, const std::string& layers) {
        const auto t0 = Clock::now();
        const DepthKind kind = parse_depth_kind(depth_kind);
        check_depth_scale(depth_scale);
        LayerSet set = LayerSet::All;
        if (layers == "final") {
            set = LayerSet::Final;
        } else if (layers != "all") {
            throw ConfigError("layers: expected 'all' or 'final', got '" + layers + "'");
        }
        const ArrayIn c = inspect_color(rgb, "rgb");
        const ArrayIn d = inspect_depth(depth, "depth");
        Layers out;
        {
            py::gil_scoped_release nogil;
            std::lock_guard<std::mutex> lock(m_mutex);
            fill_color(c, m_frame.rgb, m_threads);
            fill_depth(d, depth_scale, m_frame.depth, m_threads);
            require_same_size(m_frame.rgb, m_frame.depth, "rgb and depth");
            in_arena(m_threads, [&] {
                const Image& z = m_frame.depth;
                // Last frames' buffers, if their arrays are gone: Layers::resize keeps them.
                const int w = z.width, h = z.height;
                reuse(out.final, w, h, 3, *m_pool);
                if (set == LayerSet::All) {
                    for (Image* img : {&out.direct, &out.forward, &out.backscatter,
                                       &out.transmission, &out.normal}) {
                        reuse(*img, w, h, 3, *m_pool);
                    }
                    reuse(out.depth, w, h, 1, *m_pool);
                }
                const auto tc = Clock::now();
                m_renderer->render(out, m_frame, set, kind);
                m_composite_s = seconds_since(tc);
            });
        }
        py::dict result = layers_dict(out, m_pool);
        m_total_s = seconds_since(t0);
        return result;
    }

    py::dict camera() const { return camera_dict(m_renderer->camera()); }
    py::dict timing() const {
        py::dict d;
        d["composite_s"] = m_composite_s.load();
        d["call_s"] = m_total_s.load();
        return d;
    }
    const PyAsset& asset() const { return m_asset; }

private:
    PyAsset m_asset;
    int m_threads = 0;
    std::unique_ptr<deepsea::Renderer> m_renderer;  ///< on m_asset's asset, which it keeps alive
    Frame m_frame;                                  ///< input pixels, reused between frames
    std::shared_ptr<BufferPool> m_pool = std::make_shared<BufferPool>();
    std::mutex m_mutex;
    std::atomic<double> m_composite_s{0.0}, m_total_s{0.0};  // the last frame's, any thread
};

py::dict info(const py::object& file, int threads) {
    check_threads(threads);
    const std::string path = path_text(file);
    std::string json;
    {
        py::gil_scoped_release nogil;
        const AssetFileSummary s = read_asset_summary(path);
        Asset asset;
        in_arena(threads, [&] { asset = load_asset(path); });
        json = asset_info_json(path, s, asset);
    }
    return json_loads(json);
}

PyAsset bake_asset(const py::object& setup, const py::object& camera, const py::object& rig,
                   const py::object& water, const py::object& output_path, int xy_step,
                   int depth_samples, const std::string& depth_scheme, const py::object& z_max,
                   double tolerance, bool check, bool strict, const std::string& scattering,
                   int paths, int ms_stride, std::uint64_t seed, bool half, bool preview,
                   int threads) {
    check_threads(threads);
    BakeSettings s;
    s.step = xy_step;
    s.depth_samples = depth_samples;
    s.scheme = parse_depth_scheme(depth_scheme);
    if (py::isinstance<py::str>(z_max)) {
        if (z_max.cast<std::string>() != "auto") {
            throw ConfigError("z_max: expected a depth > 0 in metres or 'auto', got '" +
                              z_max.cast<std::string>() + "'");
        }
        s.z_max = 0.0;
    } else {
        s.z_max = z_max.cast<double>();
        if (!(s.z_max > 0.0)) {
            throw ConfigError("z_max: expected a depth > 0 in metres or 'auto', got " +
                              std::to_string(s.z_max));
        }
    }
    s.tolerance = tolerance;
    s.check = check;
    s.strict = strict;
    s.scattering = parse_scattering(scattering);
    s.higher_orders.paths = paths;
    s.higher_orders.stride = ms_stride;
    s.higher_orders.seed = seed;
    validate(s);
    Setup full = full_setup(setup, camera, rig, water);
    require_complete(full, "deepsea.bake");
    std::optional<std::string> output;
    if (!output_path.is_none()) output = path_text(output_path);
    if (output) require_writable(*output);  // before a long bake, not after
    auto a = std::make_shared<Asset>();
    {
        py::gil_scoped_release nogil;
        *a = bake(*full.camera, *full.rig, *full.water, s, {threads});
        if (output) {
            WriteOptions w;
            w.half = half;
            w.preview = preview;
            write_asset(*output, *a, w);
        }
    }
    return {std::move(a), output.value_or("")};
}

py::dict reference(const py::object& setup, const py::object& rgb, const py::object& depth,
                   const py::object& camera, const py::object& rig, const py::object& water,
                   const std::string& depth_kind, double depth_scale, double z_max, double rel_tol,
                   int threads) {
    check_threads(threads);
    check_depth_scale(depth_scale);
    const DepthKind kind = parse_depth_kind(depth_kind);
    if (!(z_max >= 0.0)) throw ConfigError("z_max: must be >= 0 metres (0: until negligible)");
    if (!(rel_tol > 0.0)) throw ConfigError("rel_tol: must be > 0");
    ReferenceOptions opt;
    opt.quadrature.rel_tol = rel_tol;
    opt.open_water_z = z_max;
    validate(opt.quadrature);
    Setup full = full_setup(setup, camera, rig, water);
    require_complete(full, "deepsea.reference");
    const ArrayIn c = inspect_color(rgb, "rgb");
    const ArrayIn d = inspect_depth(depth, "depth");
    Layers out;
    {
        py::gil_scoped_release nogil;
        Frame f;
        fill_color(c, f.rgb, threads);
        fill_depth(d, depth_scale, f.depth, threads);
        require_same_size(f.rgb, f.depth, "rgb and depth");
        to_planar_depth(*full.camera, f.depth, kind);
        out =
            render_reference(*full.camera, *full.rig, *full.water, f.rgb, f.depth, opt, {threads});
    }
    return layers_dict(out);
}

double exposure_of(const py::object& radiance, const py::object& exposure) {
    Exposure e;
    if (py::isinstance<py::str>(exposure)) {
        e = parse_exposure(exposure.cast<std::string>());
    } else {
        e = parse_exposure(py::str(exposure).cast<std::string>());
    }
    const ArrayIn in = inspect_color(radiance, "radiance");
    if (in.elem != Elem::F32 && in.elem != Elem::F64) {
        throw InputError("radiance: expected float32 or float64 linear radiance, got " +
                         std::string(in.elem == Elem::U8 ? "uint8" : "uint16"));
    }
    py::gil_scoped_release nogil;
    Image img;
    fill_color(in, img, 0, /*albedo=*/false);  // radiance: the exposure skips what is not finite
    return exposure_factor(e, img);
}

}  // namespace

}  // namespace deepsea::python

using namespace deepsea;
using namespace deepsea::python;

PYBIND11_MODULE(deepsea, m) {
    m.doc() =
        "deepsea: a physically based deep-sea camera simulator (docs/python.md). Arrays in and "
        "out are NumPy, images (H, W, C) with rows top to bottom, colour R, G, B.";
    m.attr("__version__") = DEEPSEA_VERSION;
    register_errors(m);

    py::class_<PyAsset>(m, "Asset", "A baked asset (camera x rig x water), loaded once.")
        .def_property_readonly(
            "path",
            [](const PyAsset& a) -> py::object {
                if (a.path.empty()) return py::none();
                return py::str(a.path);
            },
            "file it was loaded from or written to (None: baked in memory only)")
        .def_property_readonly(
            "camera", [](const PyAsset& a) { return camera_dict(a.asset->info.camera); },
            "the camera it was baked for (dict: width, height, fx, fy, cx, cy)")
        .def_property_readonly(
            "bake_info",
            [](const PyAsset& a) { return json_loads(bake_info_to_json(a.asset->info)); },
            "the deepsea:bake metadata (dict: camera, rig, water, lattice, check, ...)")
        .def(
            "save",
            [](const PyAsset& a, const py::object& file, bool half, bool preview) {
                const std::string path = path_text(file);
                WriteOptions w;
                w.half = half;
                w.preview = preview;
                py::gil_scoped_release nogil;
                write_asset(path, *a.asset, w);
            },
            py::arg("path"), py::kw_only(), py::arg("half") = true, py::arg("preview") = true,
            "writes the asset to a .vdb file (atomically)")
        .def("__repr__", [](const PyAsset& a) {
            const Lattice& l = a.asset->lattice();
            return "<deepsea.Asset " + describe(a.asset->info.camera) + ", " +
                   std::to_string(l.ni) + "x" + std::to_string(l.nj) + "x" +
                   std::to_string(l.nk()) + " lattice" +
                   (a.path.empty() ? std::string() : ", " + a.path) + ">";
        });

    m.def("load_asset", &load, py::arg("path"), py::kw_only(), py::arg("threads") = 0,
          "Loads a baked asset (.vdb). Raises IoError (unreadable) or AssetError (not an "
          "asset, truncated, unknown format).");

    py::class_<PyRenderer>(m, "Renderer",
                           "Composites RGB-D frames with one asset; keeps its buffers between "
                           "frames of one size. One frame at a time per renderer.")
        .def(
            py::init([](const PyAsset& asset, const py::object& camera, bool forward, int threads) {
                return std::make_unique<PyRenderer>(asset, camera, forward, threads);
            }),
            py::arg("asset"), py::kw_only(), py::arg("camera") = py::none(),
            py::arg("forward") = true, py::arg("threads") = 0,
            "camera: the frames' camera (dict, YAML text or file; default: the asset's, "
            "resampled to the frame size); forward=False leaves forward scatter out; "
            "threads: worker threads (0: all cores)")
        .def("render", &PyRenderer::render, py::arg("rgb"), py::arg("depth"), py::kw_only(),
             py::arg("depth_kind") = "z", py::arg("depth_scale") = 0.001, py::arg("layers") = "all",
             "Renders one frame. rgb: (H, W, 3) uint8/uint16 sRGB or float linear albedo "
             "((H, W, 4): alpha dropped; (H, W): grey). depth: (H, W) float metres, planar "
             "('z') or along the ray ('range'), or uint16 times depth_scale; not finite or <= 0 "
             "is open water. Returns a dict of float32 arrays: final, direct, forward, "
             "backscatter, transmission (H, W, 3), depth (H, W, planar z), normal (H, W, 3); "
             "layers='final' computes only final.")
        .def_property_readonly("camera", &PyRenderer::camera,
                               "the frames' camera (after the first frame: the one in use)")
        .def_property_readonly("asset", [](const PyRenderer& r) { return r.asset(); })
        .def_property_readonly("timing", &PyRenderer::timing,
                               "the last render: composite_s (the compositor alone) and call_s "
                               "(the whole call inside the module)");

    m.def(
        "render",
        [](const PyAsset& asset, const py::object& rgb, const py::object& depth,
           const py::object& camera, const std::string& depth_kind, double depth_scale,
           bool forward, const std::string& layers, int threads) {
            PyRenderer r(asset, camera, forward, threads);
            return r.render(rgb, depth, depth_kind, depth_scale, layers);
        },
        py::arg("asset"), py::arg("rgb"), py::arg("depth"), py::kw_only(),
        py::arg("camera") = py::none(), py::arg("depth_kind") = "z", py::arg("depth_scale") = 0.001,
        py::arg("forward") = true, py::arg("layers") = "all", py::arg("threads") = 0,
        "One frame: Renderer(asset, ...).render(rgb, depth, ...). For many frames keep a "
        "Renderer.");

    m.def("info", &info, py::arg("path"), py::kw_only(), py::arg("threads") = 0,
          "What `deepsea info --json` prints, as a dict.");

    m.def("bake", &bake_asset, py::arg("setup") = py::none(), py::kw_only(),
          py::arg("camera") = py::none(), py::arg("rig") = py::none(),
          py::arg("water") = py::none(), py::arg("output") = py::none(), py::arg("xy_step") = 0,
          py::arg("depth_samples") = 0,
          py::arg("depth_scheme") = std::string(to_string(BakeSettings{}.scheme)),
          py::arg("z_max") = "auto", py::arg("tolerance") = BakeSettings{}.tolerance,
          py::arg("check") = true, py::arg("strict") = false, py::arg("scattering") = "single",
          py::arg("paths") = HigherOrderSettings{}.paths, py::arg("ms_stride") = 0,
          py::arg("seed") = HigherOrderSettings{}.seed, py::arg("half") = true,
          py::arg("preview") = true, py::arg("threads") = 0,
          "Bakes an asset, as `deepsea bake`. setup: YAML text, a YAML file, a dict with "
          "camera/rig/water sections, or a list of these; camera=, rig=, water= add a section "
          "(dict, text or file; water also a preset such as 'jerlov:IB'). output: also write "
          "it there (.vdb). Returns the Asset.");

    m.def("reference", &reference, py::arg("setup"), py::arg("rgb"), py::arg("depth"),
          py::kw_only(), py::arg("camera") = py::none(), py::arg("rig") = py::none(),
          py::arg("water") = py::none(), py::arg("depth_kind") = "z",
          py::arg("depth_scale") = 0.001, py::arg("z_max") = 0.0, py::arg("rel_tol") = 1e-7,
          py::arg("threads") = 0,
          "Exact per-pixel rendering without an asset (`deepsea reference`): the same layers "
          "as Renderer.render. Slow by design.");

    m.def("exposure_factor", &exposure_of, py::arg("radiance"), py::arg("exposure") = "auto",
          "The factor `deepsea render --exposure` applies: 'auto' (a high percentile to 0.85, "
          "limiting clipping) or a number.");
}
