#pragma once
// deepsea's errors as Python exceptions: deepsea.Error and one subclass per library type, each
// also a subclass of the built-in exception a Python user would catch for it (ValueError,
// OSError, ...). The message is the CLI's one line.

#include <pybind11/pybind11.h>

namespace deepsea::python {

namespace py = pybind11;

/// Adds the exception types to `m` and translates deepsea's exceptions (and bad_alloc,
/// filesystem errors) into them.
void register_errors(py::module_& m);

}  // namespace deepsea::python
