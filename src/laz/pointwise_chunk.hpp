// Point-wise chunks (compressor 1 or 2): the first record raw, then every further record
// arithmetic-coded item by item, all items sharing one coder. decode_pointwise_chunk is
// declared in laz_items.hpp; the encoder (version-2 items only) is here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "laz/laz_items.hpp"

namespace beamtrace::laz {

/// The record length of `items` (the sum of their sizes).
[[nodiscard]] std::size_t record_length(std::span<const Item> items);

/// Throws CorruptData unless every item is a point-wise item of a version we decode with a
/// size that matches its type.
void check_pointwise_items(std::span<const Item> items);

/// Appends one point-wise chunk of the `point_count` records in `records` (point_count *
/// record length bytes) to `out`. The items must be POINT10, GPSTIME11, RGB12 or BYTE of
/// version 2 (std::invalid_argument otherwise).
void encode_pointwise_chunk(std::span<const Item> items, std::span<const std::uint8_t> records,
                            std::size_t point_count, std::vector<std::uint8_t>& out);

}  // namespace beamtrace::laz
