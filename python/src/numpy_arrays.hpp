// NumPy arrays in and out: checked (N, 3) and (N,) inputs that name the argument at fault, and
// std::vectors handed to NumPy without a copy.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bindings.hpp"

namespace beamtrace::python {

/// A C-contiguous array of T (converted from the caller's dtype and layout where needed).
template <typename T>
using CArray = py::array_t<T, py::array::c_style | py::array::forcecast>;

/// "(5, 2)": an array's shape as NumPy prints it.
[[nodiscard]] std::string shape_text(const py::array& a);

/// `obj` as an (N, 3) array of doubles. Raises ValueError naming `name` when it is not an array
/// of numbers (float or integer dtype) or its shape is not (N, 3).
[[nodiscard]] CArray<double> vec3_array(const py::handle& obj, const char* name);

/// `obj` as an int64 array of shape (M, 3) (`ndim` 2) or (M,) (`ndim` 1). Raises ValueError
/// naming `name` when its dtype is not an integer one or its shape is wrong.
[[nodiscard]] CArray<std::int64_t> index_array(const py::handle& obj, const char* name, int ndim);

/// Moves `v` into a NumPy array of `shape` (its size must match) that owns it: no copy.
template <typename T>
[[nodiscard]] py::array_t<T> to_numpy(std::vector<T>&& v, const std::vector<py::ssize_t>& shape) {
    auto owned = std::make_unique<std::vector<T>>(std::move(v));
    T* data = owned->data();
    py::capsule base(owned.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
    owned.release();
    return py::array_t<T>(shape, data, base);
}

}  // namespace beamtrace::python
