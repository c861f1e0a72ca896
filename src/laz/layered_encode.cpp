// encode_layered_chunk: a layered (LASzip 3) chunk as LASwritePoint writes it (the layout is in
// layered_chunk.cpp, the decoder): the first record raw, the point count, every item's layer
// sizes in item order, then the layers' bytes in the same order. Each item's encoder mirrors
// its decoder; POINT14's scanner channel selects the context of the other items.
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include "laz/item_bytes.hpp"
#include "laz/layered_bytes_encode.hpp"
#include "laz/layered_point14_encode.hpp"
#include "laz/layered_rgb_encode.hpp"
#include "laz/layered_wavepacket_encode.hpp"
#include "laz/laz_encode.hpp"

namespace beamtrace::laz {

namespace {

[[noreturn]] void refuse(const std::string& what) {
    throw std::invalid_argument("layered chunk encoder: " + what);
}

/// The record length of `items`, after checking they are a layered record LASzip writes.
[[nodiscard]] std::size_t check_items(std::span<const Item> items) {
    if (items.empty() || items[0].type != ItemType::point14) {
        refuse("the record must start with a POINT14 item");
    }
    std::size_t length = 0;
    bool colour = false;
    bool waves = false;
    for (std::size_t i = 0; i < items.size(); ++i) {
        const Item& item = items[i];
        const std::size_t size = item.type == ItemType::point14        ? 30
                                 : item.type == ItemType::rgb14        ? 6
                                 : item.type == ItemType::rgbnir14     ? 8
                                 : item.type == ItemType::wavepacket14 ? 29
                                 : item.type == ItemType::byte14       ? item.size
                                                                       : 0;
        const bool rgb = item.type == ItemType::rgb14 || item.type == ItemType::rgbnir14;
        const bool twice = (i > 0 && item.type == ItemType::point14) || (rgb && colour) ||
                           (item.type == ItemType::wavepacket14 && waves);
        if (item.version != 3 || size == 0 || item.size != size || twice) {
            refuse("no encoder for item " + std::to_string(i + 1) + " (" + item_name(item.type) +
                   ", " + std::to_string(item.size) + " bytes, version " +
                   std::to_string(item.version) + ")");
        }
        colour = colour || rgb;
        waves = waves || item.type == ItemType::wavepacket14;
        length += size;
    }
    return length;
}

/// The encoders of one chunk's items after POINT14, with their offsets in the record.
struct ItemEncoders {
    std::unique_ptr<Rgb14Encoder> rgb;
    std::size_t rgb_offset = 0;
    std::unique_ptr<WavePacket14Encoder> waves;
    std::size_t waves_offset = 0;
    std::vector<std::unique_ptr<Byte14Encoder>> extra;
    std::vector<std::size_t> extra_offsets;

    ItemEncoders(std::span<const Item> items, const std::uint8_t* first) {
        const unsigned channel = (first[15] >> 4U) & 3U;
        std::size_t offset = items[0].size;
        for (const Item& item : items.subspan(1)) {
            if (item.type == ItemType::byte14) {
                extra.push_back(
                    std::make_unique<Byte14Encoder>(first + offset, item.size, channel));
                extra_offsets.push_back(offset);
            } else if (item.type == ItemType::wavepacket14) {
                waves = std::make_unique<WavePacket14Encoder>(first + offset, channel);
                waves_offset = offset;
            } else {
                rgb = std::make_unique<Rgb14Encoder>(first + offset,
                                                     item.type == ItemType::rgbnir14, channel);
                rgb_offset = offset;
            }
            offset += item.size;
        }
    }

    void encode(const std::uint8_t* record, unsigned channel) {
        if (rgb) {
            rgb->encode(record + rgb_offset, channel);
        }
        if (waves) {
            waves->encode(record + waves_offset, channel);
        }
        for (std::size_t k = 0; k < extra.size(); ++k) {
            extra[k]->encode(record + extra_offsets[k], channel);
        }
    }
};

/// The layers of the items in record order (the decoder's order).
void finish_in_item_order(std::span<const Item> items, Point14Encoder& point, ItemEncoders& e,
                          std::vector<std::span<const std::uint8_t>>& layers) {
    point.finish(layers);
    std::size_t byte_item = 0;
    for (const Item& item : items.subspan(1)) {
        if (item.type == ItemType::byte14) {
            e.extra[byte_item++]->finish(layers);
        } else if (item.type == ItemType::wavepacket14) {
            e.waves->finish(layers);
        } else {
            e.rgb->finish(layers);
        }
    }
}

}  // namespace

void encode_layered_chunk(std::span<const Item> items, std::span<const std::uint8_t> records,
                          std::size_t point_count, std::vector<std::uint8_t>& out) {
    const std::size_t length = check_items(items);
    if (records.size() / length < point_count || records.size() != point_count * length) {
        refuse(std::to_string(records.size()) + " bytes for " + std::to_string(point_count) +
               " records of " + std::to_string(length) + " bytes");
    }
    if (point_count == 0) {
        return;
    }
    if (point_count > 0xFFFFFFFFU) {
        refuse(std::to_string(point_count) + " points in one chunk (at most 2^32 - 1)");
    }
    const std::uint8_t* first = records.data();
    Point14Encoder point(first);
    ItemEncoders others(items, first);
    for (std::size_t p = 1; p < point_count; ++p) {
        const std::uint8_t* r = first + p * length;
        others.encode(r, point.encode(r));
    }
    std::vector<std::span<const std::uint8_t>> layers;
    finish_in_item_order(items, point, others, layers);

    out.insert(out.end(), first, first + length);
    std::uint8_t word[4];
    store(word, static_cast<std::uint32_t>(point_count));
    out.insert(out.end(), word, word + 4);
    for (const std::span<const std::uint8_t> layer : layers) {
        store(word, static_cast<std::uint32_t>(layer.size()));
        out.insert(out.end(), word, word + 4);
    }
    for (const std::span<const std::uint8_t> layer : layers) {
        out.insert(out.end(), layer.begin(), layer.end());
    }
}

}  // namespace beamtrace::laz
