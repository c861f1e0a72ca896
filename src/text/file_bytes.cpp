#include "text/file_bytes.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "beamtrace/core/error.hpp"

namespace beamtrace::detail {

std::string read_file_bytes(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        throw InputError(path.string(), "is a directory, not a file");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw InputError(path.string(), std::string("cannot open: ") + std::strerror(errno));
    }
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) {
        throw InputError(path.string(), "cannot determine the file size");
    }
    in.seekg(0, std::ios::beg);
    std::string bytes(static_cast<std::size_t>(size), '\0');
    if (size > 0 && !in.read(bytes.data(), static_cast<std::streamsize>(size))) {
        throw InputError(path.string(), "read error");
    }
    return bytes;
}

}  // namespace beamtrace::detail
