// The chunk table of a LAZ file: where each chunk's bytes lie and how many points it holds.
//
// The point data starts with an i64, the offset of the table (-1: the writer could not seek
// back, and the offset is the file's last 8 bytes). The chunks follow that i64. The table: version
// u32 (0), chunk count u32, then per chunk its point count (variable-size chunks only) and byte
// size, each coded by an IntegerCompressor(32 bits, 2 contexts) against the previous chunk's
// value. Point-wise files of compressor 1 have no table: one stream holds every point.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "laz/laz_vlr.hpp"

namespace beamtrace::laz {

struct Chunk {
    std::uint64_t offset = 0;       ///< file offset of the chunk's first byte
    std::uint64_t bytes = 0;        ///< its compressed size
    std::uint64_t first_point = 0;  ///< index of its first point
    std::uint64_t points = 0;       ///< how many points it holds
};

/// Reads `size` bytes at file offset `offset` into `data` (throws on a short read).
using ReadAt = std::function<void(void* data, std::size_t size, std::uint64_t offset)>;

struct PointDataExtent {
    std::uint64_t start = 0;  ///< offset to point data (header field)
    std::uint64_t end = 0;    ///< where the point data must end (first EVLR or file end)
    std::uint64_t file_size = 0;
    std::uint64_t point_count = 0;  ///< the header's
};

/// The chunks of the file, in file order, covering exactly `extent.point_count` points. Every
/// count and offset is checked against the file before anything is allocated: a table claiming
/// more chunks than the file has bytes is refused. Without a usable table, layered chunks are
/// found by a scan (each chunk starts with its point count and layer sizes) and a point-wise file
/// of one chunk is that chunk; otherwise throws CorruptData ("chunk table: ...").
[[nodiscard]] std::vector<Chunk> read_chunk_table(const LazVlr& vlr, const PointDataExtent& extent,
                                                  const ReadAt& read);

}  // namespace beamtrace::laz
