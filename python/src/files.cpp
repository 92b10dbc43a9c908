#include "files.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "convert.h"
#include "deepsea/batch/frame_files.h"
#include "deepsea/batch/layer_files.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"

namespace deepsea::python {

namespace {

/// A vector's elements as an (H, W, C) array that owns them (moved: no copy).
template <class T>
py::array owning_array(std::vector<T>&& v, int height, int width, int channels) {
    auto* owned = new std::vector<T>(std::move(v));
    const py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>({py::ssize_t(height), py::ssize_t(width), py::ssize_t(channels)},
                          owned->data(), owner);
}

py::dict read_frame_files(const py::object& rgb, const py::object& depth,
                          const std::string& depth_channel, double depth_scale) {
    check_depth_scale(depth_scale);
    FrameJob job;
    job.rgb = path_text(rgb);
    job.depth = path_text(depth);
    DepthReadOptions opt;
    opt.channel = depth_channel;
    opt.scale = depth_scale;
    Frame f;
    {
        py::gil_scoped_release nogil;
        read_frame(job, opt, f);
    }
    py::dict out;
    if (f.coded()) {  // PNG and JPEG: the files' sRGB codes, as the CLI's compositor reads them
        SrgbCodes& c = f.codes;
        out["rgb"] = c.bits == 16 ? owning_array(std::move(c.rgb16), c.height, c.width, 3)
                                  : owning_array(std::move(c.rgb8), c.height, c.width, 3);
        out["encoding"] = "srgb";
    } else {  // other formats: read_color's linear RGB
        out["rgb"] = to_array(std::move(f.rgb));
        out["encoding"] = "linear";
    }
    out["depth"] = to_array(std::move(f.depth));
    return out;
}

ImageMetadata metadata_of(const py::handle& metadata) {
    ImageMetadata meta;
    if (metadata.is_none()) return meta;
    if (!py::isinstance<py::dict>(metadata))
        throw ConfigError("metadata: expected a dict of str to str");
    for (const auto& kv : metadata.cast<py::dict>()) {
        if (!py::isinstance<py::str>(kv.first) || !py::isinstance<py::str>(kv.second))
            throw ConfigError("metadata: expected a dict of str to str, got the entry " +
                              py::repr(kv.first).cast<std::string>() + ": " +
                              py::repr(kv.second).cast<std::string>());
        meta.emplace_back(kv.first.cast<std::string>(), kv.second.cast<std::string>());
    }
    return meta;
}

void write_image(const py::object& file, const py::object& image, const py::object& encoding,
                 double exposure, int bits, const py::object& metadata, int threads) {
    check_threads(threads);
    const std::string path = path_text(file);
    if (bits != 8 && bits != 16)
        throw ConfigError("bits: expected 8 or 16, got " + std::to_string(bits));
    if (!(exposure > 0.0) || !std::isfinite(exposure))
        throw ConfigError("exposure: must be a finite factor > 0, got " + std::to_string(exposure));
    ArrayIn in = inspect_color(image, "image");
    const bool codes = in.elem == Elem::U8 || in.elem == Elem::U16;
    set_color_encoding(in, encoding, "image");
    const bool linear = in.encoding == ColorEncoding::Linear;
    if (codes && linear)
        throw ConfigError("image: integer samples are codes: encoding='srgb' (or None)");
    if (!linear && exposure != 1.0)
        throw ConfigError("exposure: applies to linear radiance (encoding='linear') only");
    const ImageMetadata meta = metadata_of(metadata);
    require_writable_image(path);
    py::gil_scoped_release nogil;
    Image img;
    if (linear) {
        fill_color(in, img, threads, /*albedo=*/false);
        write_color(path, img, bits, meta, exposure);
        return;
    }
    // Codes or encoded values in [0, 1]: written as codes, with no curve (write_display).
    in.encoding = ColorEncoding::Linear;  // integer codes to code / top, floats as they are
    fill_color(in, img, threads, /*albedo=*/false);
    write_display(path, img, codes ? (in.elem == Elem::U8 ? 8 : 16) : bits, meta);
}

void write_layer_file(const py::object& file, const py::dict& layers, bool half,
                      const py::object& metadata, int threads) {
    check_threads(threads);
    const std::string path = path_text(file);
    const ImageMetadata meta = metadata_of(metadata);
    std::vector<std::pair<std::string, ArrayIn>> given;
    std::string names;
    for (const auto& kv : layers) {
        const std::string name = py::str(kv.first).cast<std::string>();
        // A port's mask is written with every layer, as render --layers writes it.
        if (name != "mask") names += (names.empty() ? "" : ",") + name;
        given.emplace_back(name, name == "depth" || name == "mask"
                                     ? inspect_depth(kv.second, name)
                                     : inspect_color(kv.second, name));
    }
    if (names.empty()) throw ConfigError("layers: no layer given");
    for (const auto& [name, in] : given) {
        require_same_size(given.front().second.width, given.front().second.height, in.width,
                          in.height, given.front().first + " and " + name);
    }
    LayerOutput out = parse_layers(py::str(names));
    out.half = half;
    require_writable_image(path, /*exr_only=*/true);
    py::gil_scoped_release nogil;
    Layers l;
    for (auto& [name, in] : given) {
        Image* img = name == "final"          ? &l.final
                     : name == "direct"       ? &l.direct
                     : name == "forward"      ? &l.forward
                     : name == "backscatter"  ? &l.backscatter
                     : name == "transmission" ? &l.transmission
                     : name == "depth"        ? &l.depth
                     : name == "mask"         ? &l.mask
                                              : &l.normal;
        if (name == "depth" || name == "mask") {
            fill_depth(in, 1.0, *img, threads);
        } else {
            fill_color(in, *img, threads, /*albedo=*/false);
        }
    }
    write_layers(path, l, meta, out);
}

}  // namespace

void register_files(py::module_& m) {
    m.def("read_frame", &read_frame_files, py::arg("rgb"), py::arg("depth"), py::kw_only(),
          py::arg("depth_channel") = "", py::arg("depth_scale") = DepthReadOptions{}.scale,
          "Reads one RGB-D frame's files as `deepsea render --rgb --depth` does (the same "
          "decoders, depth channels and scales). Returns a dict: rgb (PNG, JPEG: (H, W, 3) "
          "uint8 or uint16 sRGB codes; other formats: float32 linear), encoding ('srgb' or "
          "'linear'), depth ((H, W) float32 metres, as in the file: planar or range). "
          "Renderer.render(**frame) renders it as the CLI does.");
    m.def("write_image", &write_image, py::arg("path"), py::arg("image"), py::kw_only(),
          py::arg("encoding") = py::none(), py::arg("exposure") = 1.0, py::arg("bits") = 8,
          py::arg("metadata") = py::none(), py::arg("threads") = 0,
          "Writes an image as `deepsea render -o` does, atomically (PNG, JPEG, TIFF, EXR by "
          "the extension). image: (H, W, 3) float linear radiance (encoding='linear': times "
          "exposure, sRGB-encoded at `bits` in PNG/JPEG/TIFF, linear half in EXR), float values "
          "already encoded in [0, 1] (encoding='srgb', such as Camera.record's image: written "
          "as codes, no curve), or uint8/uint16 codes (written as they are). metadata: "
          "str -> str, in the file's header.");
    m.def("write_layers", &write_layer_file, py::arg("path"), py::arg("layers"), py::kw_only(),
          py::arg("half") = false, py::arg("metadata") = py::none(), py::arg("threads") = 0,
          "Writes layers (a dict as Renderer.render returns) to one multi-layer EXR as "
          "`deepsea render --layers` does (final.R, ..., depth.Z, normal.X), atomically.");
}

}  // namespace deepsea::python
