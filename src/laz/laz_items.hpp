// The items of a LAZ point record and the two chunk decoders that the LAS reader calls.
//
// A LAZ file is a LAS file whose point records are compressed chunk by chunk (LASzip format,
// the "laszip encoded" VLR, user "laszip encoded", record 22204). The VLR lists the items that
// make up one point record (type, size in bytes, codec version) in record order; a chunk holds
// `point_count` records compressed either point-wise (compressor 1 or 2: item versions 1 and 2,
// point formats 0-5) or layered (compressor 3: item version 3, point formats 6-10, the item
// codecs of LASzip 3 with one arithmetic-coded stream per layer).
//
// Errors: a decoder throws laz::CorruptData (what went wrong, no file name: the reader adds the
// file and the chunk) on any inconsistency or truncated input; it never reads outside `bytes`
// and never writes outside `out`, whatever the bytes say.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace beamtrace::laz {

/// LASzip item types (the numbers are the format's).
enum class ItemType : std::uint16_t {
    byte = 0,
    point10 = 6,
    gpstime11 = 7,
    rgb12 = 8,
    wavepacket13 = 9,
    point14 = 10,
    rgb14 = 11,
    rgbnir14 = 12,
    wavepacket14 = 13,
    byte14 = 14,
};

/// One item of the record: `size` bytes (point10: 20, gpstime11: 8, rgb12: 6, point14: 30,
/// rgb14: 6, rgbnir14: 8, byte/byte14: the extra bytes), codec `version`.
struct Item {
    ItemType type = ItemType::byte;
    std::uint16_t size = 0;
    std::uint16_t version = 0;
};

/// The name of an item type ("POINT10", ...), or "item <n>" for an unknown number.
[[nodiscard]] std::string item_name(ItemType type);

/// Corrupt or truncated compressed data (the reader turns it into an InputError naming the
/// file and the chunk).
class CorruptData : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Decodes one point-wise chunk (compressor 1 or 2; items of version 1 or 2) of `point_count`
/// records into `out` (point_count * record length bytes, the record length being the sum of
/// the item sizes). src/laz/pointwise_chunk.cpp.
void decode_pointwise_chunk(std::span<const Item> items, std::span<const std::uint8_t> bytes,
                            std::size_t point_count, std::span<std::uint8_t> out);

/// Decodes one layered chunk (compressor 3; items of version 3, point formats 6-10) of
/// `point_count` records into `out`. src/laz/layered_chunk.cpp.
void decode_layered_chunk(std::span<const Item> items, std::span<const std::uint8_t> bytes,
                          std::size_t point_count, std::span<std::uint8_t> out);

}  // namespace beamtrace::laz
