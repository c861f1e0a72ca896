// The header of a PLY file: format, elements and their properties.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace beamtrace::detail {

enum class PlyFormat : std::uint8_t { ascii, binary_little_endian, binary_big_endian };

enum class PlyType : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

/// Size in bytes of a binary value of this type.
[[nodiscard]] std::size_t ply_type_size(PlyType type);
[[nodiscard]] bool ply_type_is_integer(PlyType type);

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::float32;  ///< the scalar type, or the item type of a list
    bool is_list = false;
    PlyType count_type = PlyType::uint8;  ///< lists only
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;

    static constexpr std::size_t npos = static_cast<std::size_t>(-1);
    /// Index of the property called `name`, or npos.
    [[nodiscard]] std::size_t find(std::string_view property_name) const;
    /// Smallest number of bytes an instance can take in the data section.
    [[nodiscard]] std::size_t min_instance_bytes(PlyFormat format) const;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::ascii;
    std::vector<PlyElement> elements;
    std::size_t data_offset = 0;  ///< first byte after the `end_header` line
    long data_line = 0;           ///< line number of the first data line (ascii)

    /// The element called `name`, or nullptr.
    [[nodiscard]] const PlyElement* find(std::string_view element_name) const;
};

/// Parses the header at the start of `bytes`; throws InputError (with line) naming `path`.
[[nodiscard]] PlyHeader parse_ply_header(std::string_view bytes, const std::string& path);

}  // namespace beamtrace::detail
