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
#include "camera.h"
#include "convert.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/config.h"
#include "deepsea/reference/reference.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/renderer.h"
#include "errors.h"
#include "files.h"

namespace deepsea::python {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
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

/// Composites frames of one asset, keeping its scratch buffers between frames of one size.
/// One frame at a time (a lock); Python threads may share it, or use one renderer each to
/// render in parallel.
class PyRenderer {
public:
    PyRenderer(PyAsset asset, const py::object& camera, bool forward, int threads,
               const py::object& snow = py::none(), std::uint64_t snow_seed = 1)
        : m_asset(std::move(asset)),
          m_camera_arg(camera),
          m_forward(forward),
          m_threads(threads),
          m_snow_arg(snow),
          m_snow_seed(snow_seed) {
        check_threads(threads);
        RenderSettings settings;
        std::optional<CameraModel> model;
        if (!camera.is_none()) {
            const Setup section = section_from(camera, "camera");
            settings.camera = *section.camera;
            settings.port = section.port;  // rendered through (docs/ports.md)
            model = section.camera_model;
        }
        settings.forward = forward;
        settings.snow = snow_of(snow, snow_seed, model);
        m_renderer = std::make_unique<deepsea::Renderer>(*m_asset.asset, settings);
    }

    py::dict render(const py::object& rgb, const py::object& depth, const py::object& encoding,
                    const std::string& depth_kind, double depth_scale, const py::object& layers,
                    const py::object& frame_key = py::int_(0), const py::object& pose = py::none(),
                    const py::object& shutter = py::none()) {
        const auto t0 = Clock::now();
        const std::uint64_t key = frame_key_of(frame_key);
        const std::optional<CameraPose> camera_pose = pose_of(pose);
        const std::optional<Shutter> camera_shutter = shutter_of(shutter);
        const DepthKind kind = parse_depth_kind(depth_kind);
        check_depth_scale(depth_scale);
        const LayerOutput wanted = parse_layers(layers);
        const LayerSet set = wanted.compositor_set();
        ArrayIn c = inspect_color(rgb, "rgb");
        set_color_encoding(c, encoding, "rgb");
        const ArrayIn d = inspect_depth(depth, "depth");
        // The arrays' memory as it lies where the renderer reads it so (the common dtypes);
        // grey and float64 are converted into the renderer's own buffers first.
        ColorView color;
        DepthView z;
        const bool color_as_is = color_view_of(c, color);
        const bool depth_as_is = depth_view_of(d, depth_scale, z);
        Layers out;
        {
            py::gil_scoped_release nogil;
            std::lock_guard<std::mutex> lock(m_mutex);
            m_renderer->set_frame(key, camera_pose, camera_shutter);
            if (!color_as_is) {
                fill_color(c, m_rgb, m_threads);
                color = ColorView{m_rgb.data.data(), m_rgb.width, m_rgb.height, SampleType::F32,
                                  ColorEncoding::Linear};
            }
            if (!depth_as_is) {
                fill_depth(d, depth_scale, m_depth, m_threads);
                z = DepthView{m_depth.data.data(), m_depth.width, m_depth.height};
            }
            color.name = "rgb";
            z.name = "depth";
            z.kind = kind;
            in_arena(m_threads, [&] {
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
                m_renderer->render(out, color, z, set);
                m_composite_s = seconds_since(tc);
            });
        }
        py::dict result = layers_dict(out, m_pool, &wanted);
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
    /// What re-creates it (pickle): the asset and the constructor's arguments.
    py::tuple state() const {
        return py::make_tuple(m_asset, m_camera_arg, m_forward, m_threads, m_snow_arg, m_snow_seed);
    }

private:
    PyAsset m_asset;
    py::object m_camera_arg;  ///< as given (None, a dict, YAML text or a path): for pickle
    bool m_forward = true;
    int m_threads = 0;
    py::object m_snow_arg;  ///< as given: for pickle
    std::uint64_t m_snow_seed = 1;
    std::unique_ptr<deepsea::Renderer> m_renderer;  ///< on m_asset's asset, which it keeps alive
    Image m_rgb, m_depth;  ///< arrays converted (grey, float64), reused between frames
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
    s.port = full.port;  // the columns follow its water-side rays (docs/ports.md)
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
                   const py::object& encoding, const py::object& camera, const py::object& rig,
                   const py::object& water, const std::string& depth_kind, double depth_scale,
                   double z_max, double rel_tol, int threads) {
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
    opt.port = full.port;  // through a port: water-side layers and the mask, as Renderer's
    ArrayIn c = inspect_color(rgb, "rgb");
    set_color_encoding(c, encoding, "rgb");
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

PYBIND11_MODULE(_deepsea, m) {
    m.doc() =
        "deepsea: a physically based deep-sea camera simulator (docs/python.md). Arrays in and "
        "out are NumPy, images (H, W, C) with rows top to bottom, colour R, G, B.";
    m.attr("__version__") = DEEPSEA_VERSION;
    register_errors(m);
    register_camera(m);
    register_files(m);

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
        .def(py::pickle(
            [](const PyAsset& a) {
                if (a.path.empty()) {
                    throw InputError(
                        "Asset: baked in memory, it pickles as its file: save(path) first, or "
                        "bake(..., output=path)");
                }
                return py::make_tuple(a.path);
            },
            [](const py::tuple& t) { return load(t[0], 0); }))
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
                           "frames of one size. One frame at a time per renderer. Pickles as its "
                           "asset's file and its arguments (the asset is loaded again).")
        .def(py::init([](const PyAsset& asset, const py::object& camera, bool forward, int threads,
                         const py::object& snow, std::uint64_t snow_seed) {
                 return std::make_unique<PyRenderer>(asset, camera, forward, threads, snow,
                                                     snow_seed);
             }),
             py::arg("asset"), py::kw_only(), py::arg("camera") = py::none(),
             py::arg("forward") = true, py::arg("threads") = 0, py::arg("snow") = py::none(),
             py::arg("snow_seed") = 1,
             "camera: the frames' camera (dict, YAML text or file; default: the asset's, "
             "resampled to the frame size); forward=False leaves forward scatter out; "
             "threads: worker threads (0: all cores); snow: marine snow (docs/model.md): a "
             "preset's name ('abyssal', 'nepheloid', 'plume'), 'off', or a dict as the setup's "
             "snow section (docs/config.md), lit by the asset's lamps through the camera's lens; "
             "snow_seed: its particles' seed")
        .def("render", &PyRenderer::render, py::arg("rgb"), py::arg("depth"), py::kw_only(),
             py::arg("encoding") = py::none(), py::arg("depth_kind") = "z",
             py::arg("depth_scale") = 0.001, py::arg("layers") = "all", py::arg("frame_key") = 0,
             py::arg("pose") = py::none(), py::arg("shutter") = py::none(),
             "Renders one frame. rgb: (H, W, 3) colour ((H, W, 4): alpha dropped; (H, W): "
             "grey); uint8/uint16 are sRGB codes unless encoding='linear'; float32/float64 need "
             "encoding='srgb' or 'linear'. depth: (H, W) float metres, planar ('z') or along the "
             "ray ('range'), or uint16 times depth_scale; not finite or <= 0 is open water. "
             "layers: 'all', or names as `render --layer-set` takes them ('final,depth', or a "
             "list). Returns a dict of float32 arrays, those layers only (with snow: also "
             "'snow' and 'snow_id'). frame_key (int, or a str hashed as render hashes a file's "
             "name) and pose (a 4x4 camera-to-world matrix, OpenCV axes) place the snow: with a "
             "pose it is fixed in the world, without one drawn afresh for each frame_key. shutter: "
             "(open, close), the camera-to-world matrices when the shutter opens and closes: "
             "with the snow's streaks on and a pose, each particle is drawn as a motion streak.")
        .def_property_readonly("camera", &PyRenderer::camera,
                               "the frames' camera (after the first frame: the one in use)")
        .def_property_readonly("asset", [](const PyRenderer& r) { return r.asset(); })
        .def_property_readonly("timing", &PyRenderer::timing,
                               "the last render: composite_s (the compositor alone) and call_s "
                               "(the whole call inside the module)")
        .def(py::pickle([](const PyRenderer& r) { return r.state(); },
                        [](const py::tuple& t) {
                            return std::make_unique<PyRenderer>(
                                t[0].cast<PyAsset>(), t[1], t[2].cast<bool>(), t[3].cast<int>(),
                                t.size() > 4 ? py::object(t[4]) : py::none(),
                                t.size() > 5 ? t[5].cast<std::uint64_t>() : 1);
                        }));

    m.def(
        "render",
        [](const PyAsset& asset, const py::object& rgb, const py::object& depth,
           const py::object& encoding, const py::object& camera, const std::string& depth_kind,
           double depth_scale, bool forward, const py::object& layers, int threads) {
            PyRenderer r(asset, camera, forward, threads);
            return r.render(rgb, depth, encoding, depth_kind, depth_scale, layers);
        },
        py::arg("asset"), py::arg("rgb"), py::arg("depth"), py::kw_only(),
        py::arg("encoding") = py::none(), py::arg("camera") = py::none(),
        py::arg("depth_kind") = "z", py::arg("depth_scale") = 0.001, py::arg("forward") = true,
        py::arg("layers") = "all", py::arg("threads") = 0,
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
          py::kw_only(), py::arg("encoding") = py::none(), py::arg("camera") = py::none(),
          py::arg("rig") = py::none(), py::arg("water") = py::none(), py::arg("depth_kind") = "z",
          py::arg("depth_scale") = 0.001, py::arg("z_max") = 0.0, py::arg("rel_tol") = 1e-7,
          py::arg("threads") = 0,
          "Exact per-pixel rendering without an asset (`deepsea reference`): the same layers "
          "as Renderer.render. Slow by design.");

    m.def("exposure_factor", &exposure_of, py::arg("radiance"), py::arg("exposure") = "auto",
          "The factor `deepsea render --exposure` applies: 'auto' (a high percentile to 0.85, "
          "limiting clipping) or a number.");
}
