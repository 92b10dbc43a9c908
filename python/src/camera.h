#pragma once
// deepsea.Camera: the camera stage (docs/camera.md) from Python. A frame's radiance (the
// renderer's `final` layer) in, what a real camera records out, with the auto-exposure
// controller's two pure functions beside it.

#include <pybind11/pybind11.h>

#include <cstdint>

namespace deepsea::python {

namespace py = pybind11;

/// Adds the Camera class to `m`.
void register_camera(py::module_& m);

/// A frame key from frame_key=: an int in [0, 2^64) as it is; a str hashed as `deepsea render`
/// hashes a colour file's stem. ConfigError naming frame_key otherwise.
std::uint64_t frame_key_of(const py::handle& key);

}  // namespace deepsea::python
