// The library's exceptions as Python exceptions carrying the same message:
//   beamtrace.Error (Exception)            every beamtrace error
//   beamtrace.InputError (Error, ValueError)   a file could not be read or parsed
//   beamtrace.ConfigError (Error, ValueError)  impossible or inconsistent settings
//   beamtrace.OutputError (Error, OSError)     an output could not be written
#include <exception>
#include <string>

#include "beamtrace/core/error.hpp"
#include "bindings.hpp"

namespace beamtrace::python {
namespace {

constexpr const char* kModule = "beamtrace._beamtrace";

void add_exception(py::module_& m, const char* name, const py::object& bases) {
    const std::string qualified = std::string("beamtrace.") + name;
    auto cls = py::reinterpret_steal<py::object>(
        PyErr_NewException(qualified.c_str(), bases.ptr(), nullptr));
    if (!cls) {
        throw py::error_already_set();
    }
    m.add_object(name, cls);
}

// Raises the module's exception class `name` with `what`.
void raise(const char* name, const char* what) {
    const py::object cls = py::module_::import(kModule).attr(name);
    PyErr_SetString(cls.ptr(), what);
}

void translate(std::exception_ptr p) {
    try {
        if (p) {
            std::rethrow_exception(p);
        }
    } catch (const InputError& e) {
        raise("InputError", e.what());
    } catch (const ConfigError& e) {
        raise("ConfigError", e.what());
    } catch (const OutputError& e) {
        raise("OutputError", e.what());
    } catch (const Error& e) {
        raise("Error", e.what());
    }
}

}  // namespace

void bind_errors(py::module_& m) {
    add_exception(m, "Error", py::reinterpret_borrow<py::object>(PyExc_Exception));
    const py::object error = m.attr("Error");
    const auto value_error = py::reinterpret_borrow<py::object>(PyExc_ValueError);
    const auto os_error = py::reinterpret_borrow<py::object>(PyExc_OSError);
    add_exception(m, "InputError", py::make_tuple(error, value_error));
    add_exception(m, "ConfigError", py::make_tuple(error, value_error));
    add_exception(m, "OutputError", py::make_tuple(error, os_error));
    py::register_exception_translator(&translate);
}

}  // namespace beamtrace::python
