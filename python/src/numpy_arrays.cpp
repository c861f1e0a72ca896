#include "numpy_arrays.hpp"

namespace beamtrace::python {
namespace {

// `obj` as a NumPy array of numbers; ValueError naming `name` otherwise. `kinds`: the dtype
// kinds accepted ('f' float, 'i' signed, 'u' unsigned integer).
py::array numeric_array(const py::handle& obj, const char* name, const std::string& kinds) {
    py::array a = py::array::ensure(obj);
    if (!a) {
        throw py::value_error(std::string(name) + ": not an array of numbers");
    }
    if (kinds.find(a.dtype().kind()) == std::string::npos) {
        const std::string expected = kinds.find('f') != std::string::npos
                                         ? "expected float32 or float64"
                                         : "expected an integer dtype";
        throw py::value_error(std::string(name) + ": dtype " +
                              py::str(a.dtype()).cast<std::string>() + ", " + expected);
    }
    return a;
}

}  // namespace

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) {
        s += (i > 0 ? ", " : "") + std::to_string(a.shape(i));
    }
    return s + (a.ndim() == 1 ? ",)" : ")");
}

CArray<double> vec3_array(const py::handle& obj, const char* name) {
    const py::array a = numeric_array(obj, name, "fiu");
    if (a.ndim() != 2 || a.shape(1) != 3) {
        throw py::value_error(std::string(name) + ": shape " + shape_text(a) + ", expected (N, 3)");
    }
    return CArray<double>::ensure(a);
}

CArray<std::int64_t> index_array(const py::handle& obj, const char* name, int ndim) {
    const py::array a = numeric_array(obj, name, "iu");
    if (a.ndim() != ndim || (ndim == 2 && a.shape(1) != 3)) {
        throw py::value_error(std::string(name) + ": shape " + shape_text(a) + ", expected " +
                              (ndim == 2 ? "(M, 3)" : "(M,)"));
    }
    return CArray<std::int64_t>::ensure(a);
}

}  // namespace beamtrace::python
