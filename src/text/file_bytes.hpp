// Reading a whole file into memory: the io readers and the mesh loaders.
#pragma once

#include <filesystem>
#include <string>

namespace beamtrace::detail {

/// The file's bytes; throws InputError naming the file if it is a directory or cannot be opened
/// or read.
[[nodiscard]] std::string read_file_bytes(const std::filesystem::path& path);

}  // namespace beamtrace::detail
