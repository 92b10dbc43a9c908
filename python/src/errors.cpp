#include "errors.h"

#include <filesystem>
#include <new>
#include <string>

#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"

namespace deepsea::python {

// ---------------------------------------------------------------------------------------------
// Exceptions: deepsea.Error and one subclass per library type, each also a subclass of the
// built-in exception a Python user would catch for it. The message is the CLI's line.

namespace {

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

}  // namespace

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

}  // namespace deepsea::python
