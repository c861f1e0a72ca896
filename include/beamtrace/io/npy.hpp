// NumPy .npy files of 32-bit floats (format version 1.0, little-endian, C order).
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace beamtrace {

/// An array read from a .npy file: `data` in C (row-major) order, `shape` as stored.
struct NpyArray {
    std::vector<std::size_t> shape;
    std::vector<float> data;
};

/// Writes `data` (rows * cols floats, row-major) as a 2-D '<f4' array of shape (rows, cols),
/// readable by `numpy.load`. The header is padded with spaces so that the data starts at a
/// multiple of 64 bytes. Written atomically; throws OutputError naming the path.
void write_npy_f32(const std::filesystem::path& path, std::size_t rows, std::size_t cols,
                   std::span<const float> data);

/// The header write_npy_f32 writes (magic, version 1.0, the dict padded to 64 bytes): for
/// writers that put the data after it themselves. The data of a (rows, cols) array follows.
[[nodiscard]] std::string npy_f32_header(std::size_t rows, std::size_t cols);

/// Reads a .npy file holding '<f4' data in C order, any number of dimensions (format versions
/// 1.0, 2.0 and 3.0). Throws InputError naming the file on anything else.
[[nodiscard]] NpyArray read_npy_f32(const std::filesystem::path& path);

}  // namespace beamtrace
