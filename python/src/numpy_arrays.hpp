// NumPy arrays in and out: checked (N, 3) and (N,) inputs that name the argument at fault, and
// std::vectors handed to NumPy without a copy.
#pragma once

#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"

namespace beamtrace::python {

/// One column of a packed structured array.
struct Field {
    const char* name;
    const char* format;  ///< NumPy type code (native byte order, as put_field writes it)
};

/// The packed structured dtype of `fields`, in order.
inline py::dtype structured_dtype(std::span<const Field> fields) {
    py::list list;
    for (const Field& f : fields) {
        list.append(py::make_tuple(f.name, f.format));
    }
    return py::dtype::from_args(list);
}

/// Writes `value`'s bytes at record[at] and moves `at` past them (packed records).
template <class T>
void put_field(std::uint8_t* record, std::size_t& at, T value) {
    std::memcpy(record + at, &value, sizeof value);
    at += sizeof value;
}

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

/// An allocator whose resize() leaves new elements uninitialised (default-initialised): for
/// output buffers that are filled element by element afterwards, on several threads.
template <typename T>
struct UninitAllocator : std::allocator<T> {
    template <typename U>
    struct rebind {
        using other = UninitAllocator<U>;
    };
    UninitAllocator() = default;
    template <typename U>
    explicit UninitAllocator(const UninitAllocator<U>& /*other*/) {}
    template <typename U>
    void construct(U* p) {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

/// A vector for output buffers that every element of is written before it is read.
template <typename T>
using OutputVector = std::vector<T, UninitAllocator<T>>;

/// Moves `v` into a NumPy array of `shape` (its size must match) that owns it: no copy.
template <typename T, typename Alloc>
[[nodiscard]] py::array_t<T> to_numpy(std::vector<T, Alloc>&& v,
                                      const std::vector<py::ssize_t>& shape) {
    using Vector = std::vector<T, Alloc>;
    auto owned = std::make_unique<Vector>(std::move(v));
    T* data = owned->data();
    py::capsule base(owned.get(), [](void* p) { delete static_cast<Vector*>(p); });
    owned.release();
    return py::array_t<T>(shape, data, base);
}

}  // namespace beamtrace::python
