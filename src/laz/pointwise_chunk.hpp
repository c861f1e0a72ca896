// Point-wise chunks (compressor 1 or 2): the first record raw, then every further record
// arithmetic-coded item by item, all items sharing one coder. decode_pointwise_chunk is
// declared in laz_items.hpp; the encoder (the items LASzip 2 writes) is here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "laz/laz_items.hpp"

namespace beamtrace::laz {

/// The record length of `items` (the sum of their sizes).
[[nodiscard]] std::size_t record_length(std::span<const Item> items);

/// Throws CorruptData unless every item is a point-wise item of a version we decode with a
/// size that matches its type.
void check_pointwise_items(std::span<const Item> items);

/// Decodes a point-wise chunk a batch of records at a time, so that memory stays bounded where
/// one chunk holds very many points (compressor 1 has a single chunk of every point).
/// decode_pointwise_chunk is one batch of the whole chunk.
class PointwiseChunkDecoder {
  public:
    /// Throws CorruptData for items that are not point-wise ones we decode.
    PointwiseChunkDecoder(std::span<const Item> items, std::span<const std::uint8_t> bytes);
    ~PointwiseChunkDecoder();
    PointwiseChunkDecoder(PointwiseChunkDecoder&&) noexcept;
    PointwiseChunkDecoder& operator=(PointwiseChunkDecoder&&) noexcept;

    /// Decodes the next `count` records into the first count * record length bytes of `out`
    /// (std::invalid_argument if it is shorter).
    void decode(std::size_t count, std::span<std::uint8_t> out);

    [[nodiscard]] std::size_t record_length() const;
    /// Records decoded so far.
    [[nodiscard]] std::size_t decoded() const;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

/// Appends one point-wise chunk of the `point_count` records in `records` (point_count *
/// record length bytes) to `out`. The items must be POINT10, GPSTIME11, RGB12 or BYTE of
/// version 2, or WAVEPACKET13 of version 1 (std::invalid_argument otherwise).
void encode_pointwise_chunk(std::span<const Item> items, std::span<const std::uint8_t> records,
                            std::size_t point_count, std::vector<std::uint8_t>& out);

}  // namespace beamtrace::laz
