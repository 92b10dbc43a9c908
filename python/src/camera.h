#pragma once
// deepsea.Camera: the camera stage (docs/camera.md) from Python. A frame's radiance (the
// renderer's `final` layer) in, what a real camera records out, with the auto-exposure
// controller's two pure functions beside it.

#include <pybind11/pybind11.h>

namespace deepsea::python {

namespace py = pybind11;

/// Adds the Camera class to `m`.
void register_camera(py::module_& m);

}  // namespace deepsea::python
