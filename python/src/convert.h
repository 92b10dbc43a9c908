#pragma once
// Python values to deepsea's and back: setups (YAML text, a YAML file, or Python dicts, given to
// the strict YAML reader as JSON, which is YAML; or a list of those, whose sections merge as
// `deepsea bake --config a --config b`), paths, camera dicts, depth kinds, and layers as arrays.

#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "arrays.h"
#include "deepsea/batch/layer_files.h"
#include "deepsea/io/config.h"
#include "deepsea/optics/camera.h"
#include "deepsea/runtime/layers.h"
#include "deepsea/runtime/marine_snow.h"

namespace deepsea::python {

namespace py = pybind11;

/// JSON text of a Python value; NumPy scalars and arrays become numbers and lists.
std::string to_json(const py::handle& value);
/// json.loads(text).
py::object json_loads(const std::string& text);

/// True for an os.PathLike.
bool is_path(const py::handle& h);
/// A str or os.PathLike as a path (TypeError from os.fspath otherwise). A NUL character is a
/// ConfigError (a ValueError, as Python's own file functions raise): the C library would end
/// the name there and open another file.
std::string path_text(const py::handle& h);

/// One part of a setup: None, a dict {camera, rig, water}, YAML text (a str with a line break),
/// a file path (str or os.PathLike), or a list of these.
Setup setup_from(const py::handle& obj);
/// One section given on its own (camera=, rig=, water=): its dict (the section's content),
/// YAML text or a file holding that section, or for water a preset name ("jerlov:IB").
Setup section_from(const py::handle& obj, const char* name);
/// setup_from(setup) with the sections given on their own merged in; a section given twice is
/// a ConfigError.
Setup full_setup(const py::handle& setup, const py::handle& camera, const py::handle& rig,
                 const py::handle& water);

py::dict camera_dict(const Camera& c);
/// "z" or "range"; ConfigError otherwise.
DepthKind parse_depth_kind(const std::string& kind);
/// ConfigError unless scale > 0 (metres per unit of integer depth).
void check_depth_scale(double scale);

/// `layers=`: "all", or layer names as `deepsea render --layer-set` takes them (parse_layer_set:
/// comma-separated, or a list or tuple of names). ConfigError naming the unknown or repeated
/// name.
/// Marine snow from snow= (None or "off": none; a preset's name; a dict as the setup's snow
/// section, docs/config.md), its seed and the camera's lens (the default lens without one).
std::optional<SnowSettings> snow_of(const py::handle& snow, std::uint64_t seed,
                                    const std::optional<CameraModel>& model);

/// A camera pose from pose= (None: unset; a 4x4 or 3x4 camera-to-world matrix whose 3x3 part
/// is a rotation: its columns are the camera's x, y, z axes in the world, the last column its
/// centre). ConfigError naming pose= otherwise.
std::optional<CameraPose> pose_of(const py::handle& pose);

/// The shutter's poses for marine snow's motion streaks: None, or a pair (open, close) of
/// camera-to-world matrices as pose_of takes them; ConfigError naming `shutter` otherwise.
std::optional<Shutter> shutter_of(const py::handle& shutter);

LayerOutput parse_layers(const py::handle& layers);

/// Layers as a dict of arrays (moved out: no copy; their buffers return to `pool`, if given,
/// when the arrays are freed); empty layers are left out, and with `wanted` those it does not
/// name (a port's mask comes with every layer, as in a `--layers` file).
py::dict layers_dict(Layers& l, const std::shared_ptr<BufferPool>& pool = {},
                     const LayerOutput* wanted = nullptr);

}  // namespace deepsea::python
