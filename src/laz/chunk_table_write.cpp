// encode_chunk_table: the chunk table as LASwritePoint::write_chunk_table writes it (the reader
// is read_chunk_table, laz/chunk_table.cpp). Version 0 and the chunk count raw, then one
// arithmetic-coded stream (none for no chunks): per chunk its point count (variable chunks only,
// context 0) and its byte size (context 1), each against the previous chunk's value (0 for the
// first) by one IntegerCompressor(32 bits, 2 contexts).
#include <stdexcept>
#include <string>

#include "laz/arithmetic_encoder.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/item_bytes.hpp"
#include "laz/laz_encode.hpp"

namespace beamtrace::laz {

namespace {

/// A chunk's point count or byte size as the table's 32-bit value.
[[nodiscard]] std::int32_t table_value(std::uint64_t v, const char* what, std::size_t chunk) {
    if (v > 0xFFFFFFFFU) {
        throw std::invalid_argument("chunk table: chunk " + std::to_string(chunk + 1) + " has " +
                                    std::to_string(v) + " " + what + " (at most 2^32 - 1)");
    }
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(v));
}

}  // namespace

std::vector<std::uint8_t> encode_chunk_table(std::span<const Chunk> chunks, bool variable_chunks) {
    if (chunks.size() > 0xFFFFFFFFU) {
        throw std::invalid_argument("chunk table: " + std::to_string(chunks.size()) + " chunks");
    }
    std::vector<std::uint8_t> out(8);
    store(out.data(), std::uint32_t{0});
    store(out.data() + 4, static_cast<std::uint32_t>(chunks.size()));
    if (chunks.empty()) {
        return out;
    }
    ArithmeticEncoder enc(out);
    IntegerCompressor ic(32, 2);
    ic.init_compressor();
    std::int32_t last_points = 0;
    std::int32_t last_bytes = 0;
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        if (variable_chunks) {
            const std::int32_t points = table_value(chunks[i].points, "points", i);
            ic.compress(enc, last_points, points, 0);
            last_points = points;
        }
        const std::int32_t bytes = table_value(chunks[i].bytes, "bytes", i);
        ic.compress(enc, last_bytes, bytes, 1);
        last_bytes = bytes;
    }
    enc.done();
    return out;
}

}  // namespace beamtrace::laz
