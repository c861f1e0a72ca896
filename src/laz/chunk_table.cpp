#include "laz/chunk_table.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_compressor.hpp"

namespace beamtrace::laz {

namespace {

/// At most this many bytes per coded table value (a 32-bit corrector and its bit count).
constexpr std::uint64_t kMaxBytesPerValue = 6;

[[noreturn]] void corrupt(const std::string& what) {
    throw CorruptData("chunk table: " + what);
}

[[nodiscard]] std::int64_t read_i64(const ReadAt& read, std::uint64_t offset) {
    std::int64_t v = 0;
    read(&v, sizeof v, offset);
    return v;
}

/// The table's offset, or 0 when the file has none (or an unusable one).
[[nodiscard]] std::uint64_t table_offset(const PointDataExtent& e, const ReadAt& read) {
    const std::uint64_t chunks_start = e.start + 8;
    std::int64_t at = read_i64(read, e.start);
    if (at == -1 && e.file_size >= 8) {
        at = read_i64(read, e.file_size - 8);
    }
    if (at < 0 || static_cast<std::uint64_t>(at) <= chunks_start ||
        static_cast<std::uint64_t>(at) > e.file_size - std::min<std::uint64_t>(e.file_size, 8)) {
        return 0;
    }
    return static_cast<std::uint64_t>(at);
}

/// The layers of one layered chunk (the number of u32 sizes after its point count).
[[nodiscard]] std::uint64_t layer_count(const LazVlr& vlr) {
    std::uint64_t n = 0;
    for (const Item& item : vlr.items) {
        n += item.type == ItemType::point14    ? 9
             : item.type == ItemType::rgbnir14 ? 2
             : item.type == ItemType::byte14   ? item.size
                                               : 1;
    }
    return n;
}

/// Without a table, layered chunks can still be found one after the other: each says how many
/// points it holds and how long its layers are. Stops at the first chunk that does not fit.
[[nodiscard]] std::vector<Chunk> scan_layered(const LazVlr& vlr, const PointDataExtent& e,
                                              const ReadAt& read, const std::string& why) {
    const std::uint64_t head = vlr.record_length() + 4 + 4 * layer_count(vlr);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(head));
    std::vector<Chunk> chunks;
    std::uint64_t offset = e.start + 8;
    std::uint64_t first = 0;
    while (first < e.point_count) {
        const std::string where = why + "; scanning the chunks, chunk " +
                                  std::to_string(chunks.size() + 1) + " at byte " +
                                  std::to_string(offset);
        if (e.end < offset || e.end - offset < head) {
            corrupt(where + " runs past the end of the point data");
        }
        read(bytes.data(), bytes.size(), offset);
        std::uint32_t count = 0;
        std::memcpy(&count, bytes.data() + vlr.record_length(), 4);
        const std::uint64_t left = e.point_count - first;
        const bool fixed_ok =
            vlr.variable_chunks() || count == std::min<std::uint64_t>(vlr.chunk_size, left);
        if (count == 0 || count > left || !fixed_ok) {
            corrupt(where + " holds " + std::to_string(count) + " points, " + std::to_string(left) +
                    " are left");
        }
        std::uint64_t size = head;
        for (std::uint64_t i = 0; i < layer_count(vlr); ++i) {
            std::uint32_t layer = 0;
            std::memcpy(&layer, bytes.data() + vlr.record_length() + 4 + 4 * i, 4);
            size += layer;
        }
        if (e.end - offset < size) {
            corrupt(where + ": its " + std::to_string(size) + " bytes run past the point data");
        }
        chunks.push_back({offset, size, first, count});
        offset += size;
        first += count;
    }
    return chunks;
}

/// Without a table, a file of one chunk is still readable: it spans all the point data; layered
/// chunks are found by a scan.
[[nodiscard]] std::vector<Chunk> single_chunk(const LazVlr& vlr, const PointDataExtent& e,
                                              const std::string& why, const ReadAt& read) {
    if (vlr.compressor == Compressor::layered_chunked) {
        return scan_layered(vlr, e, read, why);
    }
    const bool one = !vlr.variable_chunks() && e.point_count <= vlr.chunk_size;
    if (!one) {
        corrupt(why + ", and the file's " + std::to_string(e.point_count) +
                " points span more than one chunk");
    }
    return {Chunk{e.start + 8, e.end - std::min(e.end, e.start + 8), 0, e.point_count}};
}

void decode_entries(const LazVlr& vlr, std::span<const std::uint8_t> bytes,
                    std::vector<Chunk>& chunks) {
    ArithmeticDecoder dec(bytes);
    dec.init();
    IntegerCompressor ic(32, 2);
    ic.init_decompressor();
    std::uint32_t last_points = 0;
    std::uint32_t last_bytes = 0;
    for (Chunk& c : chunks) {
        if (vlr.variable_chunks()) {
            last_points = static_cast<std::uint32_t>(
                ic.decompress(dec, static_cast<std::int32_t>(last_points), 0));
            c.points = last_points;
        }
        last_bytes = static_cast<std::uint32_t>(
            ic.decompress(dec, static_cast<std::int32_t>(last_bytes), 1));
        c.bytes = last_bytes;
    }
}

/// Offsets and first points from the sizes and counts; checks them against the file.
void place_chunks(const LazVlr& vlr, const PointDataExtent& e, std::uint64_t table_at,
                  std::vector<Chunk>& chunks) {
    std::uint64_t offset = e.start + 8;
    std::uint64_t first = 0;
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        Chunk& c = chunks[i];
        if (!vlr.variable_chunks()) {
            c.points = std::min<std::uint64_t>(vlr.chunk_size, e.point_count - first);
        }
        const std::string where =
            "chunk " + std::to_string(i + 1) + " of " + std::to_string(chunks.size());
        if (c.bytes == 0 || c.bytes > table_at - offset) {
            corrupt(where + ": " + std::to_string(c.bytes) + " bytes at byte " +
                    std::to_string(offset) + " do not fit before the table at byte " +
                    std::to_string(table_at));
        }
        if (c.points == 0 || c.points > e.point_count - first) {
            corrupt(where + ": " + std::to_string(c.points) + " points, but only " +
                    std::to_string(e.point_count - first) + " of the header's " +
                    std::to_string(e.point_count) + " are left");
        }
        c.offset = offset;
        c.first_point = first;
        offset += c.bytes;
        first += c.points;
    }
    if (first != e.point_count) {
        corrupt("the chunks hold " + std::to_string(first) + " points, the header says " +
                std::to_string(e.point_count));
    }
}

}  // namespace

std::vector<Chunk> read_chunk_table(const LazVlr& vlr, const PointDataExtent& e,
                                    const ReadAt& read) {
    if (e.point_count == 0) {
        return {};
    }
    if (vlr.compressor == Compressor::pointwise) {
        return {Chunk{e.start, e.end - std::min(e.end, e.start), 0, e.point_count}};
    }
    if (e.end < e.start + 8) {
        corrupt("the point data ends before the 8-byte table offset");
    }
    const std::uint64_t at = table_offset(e, read);
    if (at == 0) {
        return single_chunk(vlr, e, "the table offset is missing or points outside the file", read);
    }
    std::uint32_t head[2] = {};
    read(head, sizeof head, at);
    if (head[0] != 0) {
        return single_chunk(vlr, e, "unknown table version " + std::to_string(head[0]), read);
    }
    const std::uint64_t count = head[1];
    const std::uint64_t room = at - (e.start + 8);
    if (count == 0 || count > room || count > e.point_count) {
        return single_chunk(vlr, e,
                            std::to_string(count) + " chunks for " + std::to_string(e.point_count) +
                                " points in " + std::to_string(room) + " bytes",
                            read);
    }
    const std::uint64_t per_chunk = vlr.variable_chunks() ? 2 : 1;
    const std::uint64_t table_bytes =
        std::min(e.file_size - (at + 8), count * per_chunk * kMaxBytesPerValue + 16);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(table_bytes));
    read(bytes.data(), bytes.size(), at + 8);
    std::vector<Chunk> chunks(static_cast<std::size_t>(count));
    decode_entries(vlr, bytes, chunks);
    if (!vlr.variable_chunks()) {
        const std::uint64_t expected = (e.point_count + vlr.chunk_size - 1) / vlr.chunk_size;
        if (count < expected) {
            corrupt(std::to_string(count) + " chunks, but " + std::to_string(e.point_count) +
                    " points in chunks of " + std::to_string(vlr.chunk_size) + " need " +
                    std::to_string(expected));
        }
        chunks.resize(static_cast<std::size_t>(expected));
    }
    place_chunks(vlr, e, at, chunks);
    return chunks;
}

}  // namespace beamtrace::laz
