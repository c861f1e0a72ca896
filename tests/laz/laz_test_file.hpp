// A minimal, test-only parse of LAS and LAZ files: the header fields, the LASzip VLR and the
// chunk table, enough to hand each chunk to the chunk decoders. (The library's own container
// code is src/laz/laz_vlr.* and the LAS reader; this is an independent second reading.)
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/laz_items.hpp"

namespace beamtrace::laz::test {

inline std::vector<std::uint8_t> slurp(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw std::runtime_error("cannot open " + path.string());
    }
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename T>
T get(const std::vector<std::uint8_t>& b, std::size_t at) {
    if (at + sizeof(T) > b.size()) {
        throw std::runtime_error("test parse: read past the end");
    }
    T v;
    std::memcpy(&v, b.data() + at, sizeof(T));
    return v;
}

struct LasTestFile {
    std::vector<std::uint8_t> bytes;
    std::size_t point_offset = 0;
    std::size_t record_length = 0;
    std::size_t point_count = 0;
    unsigned point_format = 0;
    std::size_t vlr_count = 0;
    std::size_t header_size = 0;

    [[nodiscard]] const std::uint8_t* record(std::size_t i) const {
        return bytes.data() + point_offset + i * record_length;
    }
};

inline LasTestFile read_las_test_file(const std::filesystem::path& path) {
    LasTestFile f;
    f.bytes = slurp(path);
    f.header_size = get<std::uint16_t>(f.bytes, 94);
    f.point_offset = get<std::uint32_t>(f.bytes, 96);
    f.vlr_count = get<std::uint32_t>(f.bytes, 100);
    f.point_format = get<std::uint8_t>(f.bytes, 104) & 0x3FU;
    f.record_length = get<std::uint16_t>(f.bytes, 105);
    f.point_count = get<std::uint32_t>(f.bytes, 107);
    if (f.bytes[25] >= 4 && f.point_count == 0) {
        f.point_count = static_cast<std::size_t>(get<std::uint64_t>(f.bytes, 247));
    }
    return f;
}

struct LazChunk {
    std::size_t begin = 0;
    std::size_t size = 0;
    std::size_t points = 0;
};

struct LazTestFile {
    LasTestFile las;
    std::uint16_t compressor = 0;
    std::uint32_t chunk_size = 0;
    std::vector<Item> items;
    std::vector<LazChunk> chunks;
};

/// The LASzip VLR's items, and the chunks (from the chunk table, or the whole point data for
/// compressor 1).
inline LazTestFile read_laz_test_file(const std::filesystem::path& path) {
    LazTestFile f;
    f.las = read_las_test_file(path);
    const auto& b = f.las.bytes;
    std::size_t at = f.las.header_size;
    for (std::size_t v = 0; v < f.las.vlr_count; ++v) {
        const std::string user(reinterpret_cast<const char*>(b.data() + at + 2));
        const auto id = get<std::uint16_t>(b, at + 18);
        const auto length = get<std::uint16_t>(b, at + 20);
        const std::size_t payload = at + 54;
        if (user == "laszip encoded" && id == 22204) {
            f.compressor = get<std::uint16_t>(b, payload);
            f.chunk_size = get<std::uint32_t>(b, payload + 12);
            const auto n = get<std::uint16_t>(b, payload + 32);
            for (std::size_t i = 0; i < n; ++i) {
                const std::size_t it = payload + 34 + 6 * i;
                f.items.push_back({static_cast<ItemType>(get<std::uint16_t>(b, it)),
                                   get<std::uint16_t>(b, it + 2), get<std::uint16_t>(b, it + 4)});
            }
        }
        at = payload + length;
    }
    if (f.items.empty()) {
        throw std::runtime_error("no LASzip VLR in " + path.string());
    }
    const std::size_t data = f.las.point_offset;
    if (f.compressor == 1) {
        f.chunks.push_back({data, b.size() - data, f.las.point_count});
        return f;
    }
    const auto table = static_cast<std::size_t>(get<std::int64_t>(b, data));
    const auto count = get<std::uint32_t>(b, table + 4);
    const std::span<const std::uint8_t> coded(b.data() + table + 8, b.size() - table - 8);
    ArithmeticDecoder dec(coded);
    dec.init();
    IntegerCompressor ic(32, 2);
    ic.init_decompressor();
    const bool variable = f.chunk_size == 0xFFFFFFFFU;
    std::int32_t points = 0;
    std::int32_t size = 0;
    std::size_t begin = data + 8;
    std::size_t left = f.las.point_count;
    for (std::uint32_t c = 0; c < count; ++c) {
        if (variable) {
            points = ic.decompress(dec, points, 0);
        }
        size = ic.decompress(dec, size, 1);
        const std::size_t n =
            variable ? static_cast<std::size_t>(points) : std::min<std::size_t>(f.chunk_size, left);
        f.chunks.push_back({begin, static_cast<std::size_t>(size), n});
        begin += static_cast<std::size_t>(size);
        left -= n;
    }
    return f;
}

}  // namespace beamtrace::laz::test
