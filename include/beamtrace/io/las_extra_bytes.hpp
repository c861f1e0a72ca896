// LAS 1.4 extra bytes: the Extra Bytes VLR (user ID LASF_Spec, record ID 4) and its 192-byte
// descriptors (LAS 1.4 R15 section 2.16, Table 24), which name, type and scale the bytes each
// point record carries after its standard fields, so that readers (laspy, PDAL, copc.js) show
// them as named dimensions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/io/las.hpp"

namespace beamtrace {

/// LAS extra bytes data types (Table 25): 1 uint8 ... 10 float64; 0: undocumented bytes.
enum class LasExtraType : std::uint8_t {
    undocumented = 0,
    u8 = 1,
    i8 = 2,
    u16 = 3,
    i16 = 4,
    u32 = 5,
    i32 = 6,
    u64 = 7,
    i64 = 8,
    f32 = 9,
    f64 = 10,
};

/// Bytes a value of `type` takes (undocumented: the descriptor's `options` count them).
[[nodiscard]] std::size_t las_extra_type_size(LasExtraType type);

/// One descriptor of the Extra Bytes VLR. The options bits say which of no_data, min, max,
/// scale and offset are set (bit 0, 1, 2, 3, 4). no_data, min and max are raw (unscaled)
/// values, stored in the 8-byte slot as int64 (signed types), uint64 (unsigned) or double.
struct LasExtraBytesDescriptor {
    LasExtraType data_type = LasExtraType::u8;
    std::uint8_t options = 0;
    std::string name;  ///< up to 31 characters
    double no_data = 0.0, min = 0.0, max = 0.0;
    double scale = 1.0, offset = 0.0;
    std::string description;  ///< up to 31 characters

    static constexpr std::uint8_t kNoData = 1, kMin = 2, kMax = 4, kScale = 8, kOffset = 16;
};

/// Bytes of one descriptor in the VLR.
inline constexpr std::size_t kLasExtraBytesDescriptorBytes = 192;

/// The Extra Bytes VLR of `descriptors`, in record order. Throws ConfigError for a name longer
/// than 31 characters or an undocumented type.
[[nodiscard]] LasVlr las_extra_bytes_vlr(std::span<const LasExtraBytesDescriptor> descriptors);

/// The descriptors of the Extra Bytes VLR among `vlrs` (empty when there is none; several such
/// VLRs, as some writers make, are read one after the other). Throws InputError when one's
/// length is not a multiple of 192 bytes.
[[nodiscard]] std::vector<LasExtraBytesDescriptor> las_extra_bytes_descriptors(
    std::span<const LasVlr> vlrs);

/// Bytes per point the descriptors describe (their types' sizes).
[[nodiscard]] std::size_t las_extra_bytes_size(
    std::span<const LasExtraBytesDescriptor> descriptors);

/// The value of extra-bytes field `index` of `descriptors` in `extra` (a point's extra bytes):
/// raw * scale + offset (scale and offset applied when their option bits are set).
[[nodiscard]] double las_extra_bytes_value(std::span<const LasExtraBytesDescriptor> descriptors,
                                           std::size_t index, std::span<const std::uint8_t> extra);

}  // namespace beamtrace
