// What a LAZ writer needs from the codec: the layered chunk encoder, the LASzip VLR for a point
// format, and the chunk table that follows the last chunk (the point-wise chunk encoder is in
// laz/pointwise_chunk.hpp).
//
// Everything here is a pure function of its arguments, so chunks can be encoded on any threads
// and the file is the same for any thread count. The bytes are those LASzip writes for the same
// records (tests/laz re-encodes LASzip's chunks byte for byte).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "laz/chunk_table.hpp"
#include "laz/laz_items.hpp"
#include "laz/laz_vlr.hpp"

namespace beamtrace::laz {

/// Appends one layered chunk (compressor 3) of the `point_count` records in `records`
/// (point_count * record length bytes) to `out`: the point count, the layer sizes and the
/// layers. The items must be POINT14, RGB14, RGBNIR14, BYTE14 or WAVEPACKET14 of version 3
/// (std::invalid_argument otherwise). src/laz/layered_encode.cpp. As in LASzip, a layer whose
/// values never change within the chunk is written as 0 bytes (XY and Z always have bytes), and
/// GPS times are compared as doubles: a time that equals the channel's last one as a double
/// but not in its bits (-0.0 after 0.0) decodes as the last one's bits.
void encode_layered_chunk(std::span<const Item> items, std::span<const std::uint8_t> records,
                          std::size_t point_count, std::vector<std::uint8_t>& out);

/// The LASzip VLR that LASzip writes for LAS point format `point_format` (0-10) with
/// `record_length` bytes per record (the extra bytes become a BYTE/BYTE14 item): point-wise
/// chunked (compressor 2, items of version 2, WAVEPACKET13 of version 1) for formats 0-5,
/// layered (compressor 3, version 3) for 6-10; `chunk_size` points per chunk
/// (kVariableChunkSize: variable). LASzip library version 3.4 r3, options 0, no special EVLRs
/// (-1, -1). Throws std::invalid_argument for an impossible format or length.
/// src/laz/laz_vlr_write.cpp.
[[nodiscard]] LazVlr laz_vlr_for(int point_format, std::size_t record_length,
                                 std::uint32_t chunk_size);

/// The payload of the LASzip VLR (user "laszip encoded", record 22204) for `vlr`.
[[nodiscard]] std::vector<std::uint8_t> serialize_laz_vlr(const LazVlr& vlr);

/// The chunk table as LASzip writes it after the last chunk: version 0, the chunk count, then
/// each chunk's point count (variable chunks only) and byte size, integer-compressed.
/// read_chunk_table() reads it back. src/laz/chunk_table_write.cpp.
[[nodiscard]] std::vector<std::uint8_t> encode_chunk_table(std::span<const Chunk> chunks,
                                                           bool variable_chunks);

}  // namespace beamtrace::laz
