#include "beamtrace/io/npy.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "text/file_bytes.hpp"

namespace beamtrace {

static_assert(std::endian::native == std::endian::little,
              "the .npy writer and reader assume a little-endian host");

namespace {

constexpr std::string_view kMagic{"\x93NUMPY", 6};
constexpr std::size_t kAlignment = 64;

std::string header_text(std::size_t rows, std::size_t cols) {
    std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                       std::to_string(rows) + ", " + std::to_string(cols) + "), }";
    // magic (6) + version (2) + header length (2) + dict + padding + '\n' = k * 64
    const std::size_t unpadded = kMagic.size() + 4 + dict.size() + 1;
    const std::size_t padded = (unpadded + kAlignment - 1) / kAlignment * kAlignment;
    dict.append(padded - unpadded, ' ');
    dict.push_back('\n');
    return dict;
}

/// The text after `'key':` in the header dict, with leading spaces removed.
std::string_view dict_value(const std::string& file, std::string_view dict, std::string_view key) {
    const std::string quoted = "'" + std::string(key) + "'";
    std::size_t pos = dict.find(quoted);
    if (pos == std::string_view::npos) {
        throw InputError(file, "npy header has no '" + std::string(key) + "' entry");
    }
    pos = dict.find(':', pos + quoted.size());
    if (pos == std::string_view::npos) {
        throw InputError(file, "malformed npy header");
    }
    std::string_view value = dict.substr(pos + 1);
    value.remove_prefix(std::min(value.find_first_not_of(' '), value.size()));
    return value;
}

std::vector<std::size_t> parse_shape(const std::string& file, std::string_view value) {
    if (value.empty() || value.front() != '(') {
        throw InputError(file, "malformed npy shape");
    }
    const std::size_t close = value.find(')');
    if (close == std::string_view::npos) {
        throw InputError(file, "malformed npy shape");
    }
    std::vector<std::size_t> shape;
    const char* p = value.data() + 1;
    const char* end = value.data() + close;
    while (p < end) {
        while (p < end && (*p == ' ' || *p == ',')) {
            ++p;
        }
        if (p == end) {
            break;
        }
        std::size_t extent = 0;
        const auto [next, ec] = std::from_chars(p, end, extent);
        if (ec != std::errc{}) {
            throw InputError(
                file, "malformed npy shape '" + std::string(value.substr(0, close + 1)) + "'");
        }
        shape.push_back(extent);
        p = next;
    }
    return shape;
}

}  // namespace

std::string npy_f32_header(std::size_t rows, std::size_t cols) {
    const std::string dict = header_text(rows, cols);
    // The dict of a 2-D shape is far below the 64 KiB of a version 1.0 header.
    const auto dict_len = static_cast<std::uint16_t>(dict.size());
    const char preamble[4] = {'\x01', '\x00', static_cast<char>(dict_len & 0xffu),
                              static_cast<char>(dict_len >> 8)};
    std::string header(kMagic);
    header.append(preamble, sizeof preamble);
    return header + dict;
}

void write_npy_f32(const std::filesystem::path& path, std::size_t rows, std::size_t cols,
                   std::span<const float> data) {
    if (cols != 0 && rows > std::numeric_limits<std::size_t>::max() / cols) {
        throw OutputError(path.string() + ": array shape overflows");
    }
    if (data.size() != rows * cols) {
        throw OutputError(path.string() + ": array of shape (" + std::to_string(rows) + ", " +
                          std::to_string(cols) + ") needs " + std::to_string(rows * cols) +
                          " values, got " + std::to_string(data.size()));
    }
    AtomicFile out(path);
    out.write(npy_f32_header(rows, cols));
    out.write(data.data(), data.size_bytes());
    out.commit();
}

NpyArray read_npy_f32(const std::filesystem::path& path) {
    const std::string file = path.string();
    const std::string bytes = detail::read_file_bytes(path);
    if (bytes.size() < kMagic.size() + 4 ||
        std::string_view(bytes.data(), kMagic.size()) != kMagic) {
        throw InputError(file, "not a .npy file (bad magic bytes)");
    }
    const auto byte_at = [&](std::size_t i) { return std::size_t(std::uint8_t(bytes[i])); };
    const std::size_t major = byte_at(6);
    std::size_t header_len = 0;
    std::size_t header_start = 0;
    if (major == 1) {
        header_len = byte_at(8) | (byte_at(9) << 8);
        header_start = 10;
    } else if (major == 2 || major == 3) {
        if (bytes.size() < 12) {
            throw InputError(file, "truncated npy header");
        }
        header_len = byte_at(8) | (byte_at(9) << 8) | (byte_at(10) << 16) | (byte_at(11) << 24);
        header_start = 12;
    } else {
        throw InputError(file, "unsupported npy format version " + std::to_string(major));
    }
    if (bytes.size() - header_start < header_len) {
        throw InputError(file, "truncated npy header");
    }
    const std::string_view dict(bytes.data() + header_start, header_len);

    const std::string_view descr = dict_value(file, dict, "descr");
    if (!descr.starts_with("'<f4'")) {
        const std::size_t end = descr.find_first_of(",}");
        throw InputError(file, "unsupported npy dtype " + std::string(descr.substr(0, end)) +
                                   " (expected '<f4')");
    }
    const std::string_view fortran = dict_value(file, dict, "fortran_order");
    if (fortran.starts_with("True")) {
        throw InputError(file, "Fortran-ordered npy arrays are not supported");
    }
    if (!fortran.starts_with("False")) {
        throw InputError(file, "malformed npy fortran_order");
    }

    NpyArray array;
    array.shape = parse_shape(file, dict_value(file, dict, "shape"));
    std::size_t count = 1;
    for (const std::size_t extent : array.shape) {
        if (extent != 0 && count > std::numeric_limits<std::size_t>::max() / 4 / extent) {
            throw InputError(file, "npy shape overflows");
        }
        count *= extent;
    }
    const std::size_t data_start = header_start + header_len;
    const std::size_t data_bytes = bytes.size() - data_start;
    if (data_bytes != count * sizeof(float)) {
        throw InputError(file, "npy data holds " + std::to_string(data_bytes) +
                                   " bytes, shape needs " + std::to_string(count * sizeof(float)));
    }
    array.data.resize(count);
    if (count > 0) {
        std::memcpy(array.data.data(), bytes.data() + data_start, data_bytes);
    }
    return array;
}

}  // namespace beamtrace
