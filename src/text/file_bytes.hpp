// Reading a whole file into memory: the io readers, the mesh loaders and the config files.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace beamtrace::detail {

/// The file's bytes; throws InputError naming the file if it is a directory or cannot be opened
/// or read.
[[nodiscard]] std::string read_file_bytes(const std::filesystem::path& path);

/// The largest scene or survey file read (docs/scene-file.md, docs/survey.md): 64 MiB.
inline constexpr std::size_t kMaxConfigFileBytes = std::size_t{64} << 20;

/// The bytes of `path`, the `what` (e.g. "scene file"), which must be a regular file of at most
/// `max_bytes`; InputError naming the file (and the limit) otherwise. Never reads more than
/// `max_bytes` + 1 bytes, so a device such as /dev/zero or a file growing while read is
/// refused with little memory.
[[nodiscard]] std::string read_bounded_file(const std::filesystem::path& path,
                                            const std::string& what, std::size_t max_bytes);

/// "64 MiB": a byte limit in messages.
[[nodiscard]] std::string byte_limit_text(std::size_t bytes);

}  // namespace beamtrace::detail
