// decode_layered_chunk: the layout of a layered (LASzip 3) chunk.
//
//   first record, raw (record length bytes)
//   point count u32
//   the byte count of every layer u32, item after item (POINT14: 9, RGB14: 1, RGBNIR14: 2,
//   BYTE14: one per byte)
//   the layers' bytes, in the same order
//
// The first record is copied; every further record is decoded item by item, POINT14 first, since
// its scanner channel selects the context of the other items.
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "laz/layered_bytes.hpp"
#include "laz/layered_point14.hpp"
#include "laz/layered_rgb.hpp"
#include "laz/layered_wavepacket.hpp"
#include "laz/laz_items.hpp"

namespace beamtrace::laz {

namespace {

using Bytes = std::span<const std::uint8_t>;

[[nodiscard]] std::size_t layer_count(const Item& item) {
    switch (item.type) {
        case ItemType::point14:
            return Point14Decoder::kLayers;
        case ItemType::rgb14:
            return 1;
        case ItemType::rgbnir14:
            return 2;
        case ItemType::byte14:
            return item.size;
        case ItemType::wavepacket14:
            return 1;
        default:
            throw CorruptData(item_name(item.type) + " items (version " +
                              std::to_string(item.version) +
                              ") are not supported in layered chunks");
    }
}

void check_items(std::span<const Item> items) {
    if (items.empty() || items[0].type != ItemType::point14) {
        throw CorruptData("a layered chunk's record must start with a POINT14 item");
    }
    for (std::size_t i = 0; i < items.size(); ++i) {
        const Item& item = items[i];
        if (item.version != 3) {
            throw CorruptData(item_name(item.type) + " item version " +
                              std::to_string(item.version) + " in a layered chunk (expected 3)");
        }
        if (i > 0 && item.type == ItemType::point14) {
            throw CorruptData("a second POINT14 item in the record");
        }
        const std::size_t size = item.type == ItemType::point14    ? 30
                                 : item.type == ItemType::rgb14    ? 6
                                 : item.type == ItemType::rgbnir14 ? 8
                                                                   : item.size;
        if (item.size != size || size == 0) {
            throw CorruptData(item_name(item.type) + " item of " + std::to_string(item.size) +
                              " bytes");
        }
    }
}

/// Splits the chunk after its first record into the layers of every item.
[[nodiscard]] std::vector<Bytes> split_layers(std::span<const Item> items, Bytes rest,
                                              std::size_t point_count) {
    if (rest.size() < 4) {
        throw CorruptData("chunk ends before its point count");
    }
    std::uint32_t count = 0;
    std::memcpy(&count, rest.data(), 4);
    if (count != point_count) {
        throw CorruptData("chunk holds " + std::to_string(count) + " points, expected " +
                          std::to_string(point_count));
    }
    std::size_t layers = 0;
    for (const Item& item : items) {
        layers += layer_count(item);
    }
    std::size_t pos = 4;
    if ((rest.size() - pos) / 4 < layers) {
        throw CorruptData("chunk ends inside its table of " + std::to_string(layers) +
                          " layer sizes");
    }
    std::vector<Bytes> out(layers);
    std::uint64_t data = pos + 4 * std::uint64_t{layers};
    for (std::size_t i = 0; i < layers; ++i, pos += 4) {
        std::uint32_t size = 0;
        std::memcpy(&size, rest.data() + pos, 4);
        if (size > rest.size() - data) {
            throw CorruptData("layer " + std::to_string(i + 1) + " of " + std::to_string(layers) +
                              " (" + std::to_string(size) + " bytes) runs past the chunk's end");
        }
        out[i] = rest.subspan(static_cast<std::size_t>(data), size);
        data += size;
    }
    return out;
}

}  // namespace

void decode_layered_chunk(std::span<const Item> items, std::span<const std::uint8_t> bytes,
                          std::size_t point_count, std::span<std::uint8_t> out) {
    check_items(items);
    std::size_t record = 0;
    for (const Item& item : items) {
        record += item.size;
    }
    if (out.size() / record < point_count || out.size() != point_count * record) {
        throw CorruptData("output of " + std::to_string(out.size()) + " bytes for " +
                          std::to_string(point_count) + " records of " + std::to_string(record) +
                          " bytes");
    }
    if (point_count == 0) {
        return;
    }
    if (bytes.size() < record) {
        throw CorruptData("chunk of " + std::to_string(bytes.size()) +
                          " bytes ends inside its first record");
    }
    std::memcpy(out.data(), bytes.data(), record);
    const std::vector<Bytes> layers = split_layers(items, bytes.subspan(record), point_count);

    // The decoders of the items after POINT14, with their offsets in the record.
    Point14Decoder point(bytes.data(), std::span(layers).first(Point14Decoder::kLayers));
    const unsigned channel = (bytes[15] >> 4U) & 3U;
    std::optional<Rgb14Decoder> rgb;
    std::size_t rgb_offset = 0;
    std::unique_ptr<WavePacket14Decoder> waves;
    std::size_t waves_offset = 0;
    std::vector<std::unique_ptr<Byte14Decoder>> extra;
    std::vector<std::size_t> extra_offsets;
    std::size_t offset = items[0].size;
    std::size_t layer = Point14Decoder::kLayers;
    for (std::size_t i = 1; i < items.size(); ++i) {
        const Item& item = items[i];
        const std::size_t n = layer_count(item);
        if (item.type == ItemType::wavepacket14 && !waves) {
            waves = std::make_unique<WavePacket14Decoder>(bytes.data() + offset, layers[layer],
                                                          channel);
            waves_offset = offset;
        } else if (item.type == ItemType::byte14) {
            extra.push_back(std::make_unique<Byte14Decoder>(
                bytes.data() + offset, std::span(layers).subspan(layer, n), channel));
            extra_offsets.push_back(offset);
        } else if (item.type != ItemType::wavepacket14 && !rgb) {
            const bool nir = item.type == ItemType::rgbnir14;
            rgb.emplace(bytes.data() + offset, nir, layers[layer],
                        nir ? layers[layer + 1] : Bytes{}, channel);
            rgb_offset = offset;
        } else {
            throw CorruptData("two colour or wave packet items in the record");
        }
        offset += item.size;
        layer += n;
    }

    for (std::size_t p = 1; p < point_count; ++p) {
        std::uint8_t* r = out.data() + p * record;
        const unsigned c = point.decode(r);
        if (rgb) {
            rgb->decode(r + rgb_offset, c);
        }
        if (waves) {
            waves->decode(r + waves_offset, c);
        }
        for (std::size_t k = 0; k < extra.size(); ++k) {
            extra[k]->decode(r + extra_offsets[k], c);
        }
    }
}

}  // namespace beamtrace::laz
