// Reading a whole file into memory for the mesh loaders.
#pragma once

#include <filesystem>
#include <string>

namespace beamtrace::detail {

/// The file's bytes; throws InputError if it cannot be opened or read.
[[nodiscard]] std::string read_file_bytes(const std::filesystem::path& path);

}  // namespace beamtrace::detail
