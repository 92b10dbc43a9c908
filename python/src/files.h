#pragma once
// Files in and out as the CLI reads and writes them: deepsea.read_frame (batch's read_frame:
// the same decoders, depth channels and scales), deepsea.write_image (the exposed image's
// writers: PNG by ISA-L igzip, JPEG by libjpeg-turbo, EXR by OpenEXR) and deepsea.write_layers
// (a `--layers` EXR).

#include <pybind11/pybind11.h>

namespace deepsea::python {

namespace py = pybind11;

/// Adds read_frame, write_image and write_layers to `m`.
void register_files(py::module_& m);

}  // namespace deepsea::python
