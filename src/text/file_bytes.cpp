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

std::string byte_limit_text(std::size_t bytes) {
    constexpr std::size_t kMiB = std::size_t{1} << 20;
    if (bytes >= kMiB && bytes % kMiB == 0) {
        return std::to_string(bytes / kMiB) + " MiB";
    }
    return std::to_string(bytes) + " bytes";
}

std::string read_bounded_file(const std::filesystem::path& path, const std::string& what,
                              std::size_t max_bytes) {
    const std::string name = path.string();
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (ec) {
        throw InputError(name, "cannot open the " + what + ": " + ec.message());
    }
    if (!std::filesystem::is_regular_file(st)) {
        throw InputError(name, "the " + what + " is not a regular file" +
                                   (std::filesystem::is_directory(st) ? " (a directory)" : ""));
    }
    const std::string too_large = "the " + what + " is larger than the limit of " +
                                  byte_limit_text(max_bytes) + " for " + what + "s";
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > max_bytes) {
        throw InputError(name, too_large);
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw InputError(name, "cannot open the " + what + ": " + std::strerror(errno));
    }
    std::string bytes(static_cast<std::size_t>(ec ? 0 : size), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    bytes.resize(static_cast<std::size_t>(in.gcount()));
    // The file may have grown since its size was taken: read on, up to the limit.
    char chunk[65536];
    while (in && bytes.size() <= max_bytes) {
        in.read(chunk, sizeof chunk);
        bytes.append(chunk, static_cast<std::size_t>(in.gcount()));
    }
    if (bytes.size() > max_bytes) {
        throw InputError(name, too_large);
    }
    if (in.bad()) {
        throw InputError(name, "read error in the " + what);
    }
    return bytes;
}

}  // namespace beamtrace::detail
