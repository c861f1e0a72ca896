// The LASzip VLR (user "laszip encoded", record 22204): how the point records are compressed.
//
// Layout (little-endian): compressor u16, coder u16, version major u8, minor u8, revision u16,
// options u32, chunk size u32, number of special EVLRs i64, offset to special EVLRs i64, item
// count u16, then per item type u16, size u16, version u16.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "laz/laz_items.hpp"

namespace beamtrace::laz {

/// How the records are compressed (the VLR's compressor field).
enum class Compressor : std::uint16_t {
    none = 0,
    pointwise = 1,          ///< one stream for the whole file (LASzip 1.x)
    pointwise_chunked = 2,  ///< point-wise, in chunks
    layered_chunked = 3,    ///< LASzip 3 layered items, in chunks
};

/// The chunk size that marks variable-size chunks (each chunk's point count in the table).
inline constexpr std::uint32_t kVariableChunkSize = 0xFFFFFFFFU;

struct LazVlr {
    Compressor compressor = Compressor::none;
    std::uint16_t coder = 0;
    std::uint8_t version_major = 0;
    std::uint8_t version_minor = 0;
    std::uint16_t version_revision = 0;
    std::uint32_t options = 0;
    std::uint32_t chunk_size = 0;
    std::int64_t special_evlr_count = -1;
    std::int64_t special_evlr_offset = -1;
    std::vector<Item> items;

    /// The record length the items make up (sum of their sizes).
    [[nodiscard]] std::size_t record_length() const;
    [[nodiscard]] bool variable_chunks() const { return chunk_size == kVariableChunkSize; }
};

/// Parses the VLR payload and checks it against the file's point format (0-10, the LAZ bits
/// cleared) and record length: known compressor, coder and item types, item sizes and versions
/// valid for their types, items that make up exactly that record for that format (point-wise
/// items for formats 0-5, layered ones for 6-10). Throws CorruptData saying what is wrong.
[[nodiscard]] LazVlr parse_laz_vlr(std::span<const std::uint8_t> data, int point_format,
                                   std::size_t record_length);

}  // namespace beamtrace::laz
