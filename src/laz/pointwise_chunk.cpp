// Decoding and encoding of point-wise chunks.
#include "laz/pointwise_chunk.hpp"

#include <cstring>
#include <stdexcept>
#include <string>
#include <variant>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/items_v1.hpp"
#include "laz/items_v2.hpp"

namespace beamtrace::laz {
namespace {

using ItemDecoder =
    std::variant<Point10DecoderV1, Gpstime11DecoderV1, Rgb12DecoderV1, ByteDecoderV1,
                 Wavepacket13CodecV1, Point10CodecV2, Gpstime11CodecV2, Rgb12CodecV2, ByteCodecV2>;
using ItemEncoder =
    std::variant<Point10CodecV2, Gpstime11CodecV2, Rgb12CodecV2, ByteCodecV2, Wavepacket13CodecV1>;

std::string describe(const Item& item) {
    return item_name(item.type) + " version " + std::to_string(item.version) + " (" +
           std::to_string(item.size) + " bytes)";
}

/// The fixed size of a type's item, 0 for BYTE (any size from 1).
std::uint16_t fixed_size(ItemType type) {
    switch (type) {
        case ItemType::point10:
            return 20;
        case ItemType::gpstime11:
            return 8;
        case ItemType::rgb12:
            return 6;
        case ItemType::wavepacket13:
            return 29;
        default:
            return 0;
    }
}

void emplace_decoder(std::vector<ItemDecoder>& decoders, const Item& item) {
    const bool v1 = item.version == 1;
    switch (item.type) {
        case ItemType::point10:
            v1 ? (void)decoders.emplace_back(std::in_place_type<Point10DecoderV1>)
               : (void)decoders.emplace_back(std::in_place_type<Point10CodecV2>, false);
            return;
        case ItemType::gpstime11:
            v1 ? (void)decoders.emplace_back(std::in_place_type<Gpstime11DecoderV1>)
               : (void)decoders.emplace_back(std::in_place_type<Gpstime11CodecV2>, false);
            return;
        case ItemType::rgb12:
            v1 ? (void)decoders.emplace_back(std::in_place_type<Rgb12DecoderV1>)
               : (void)decoders.emplace_back(std::in_place_type<Rgb12CodecV2>, false);
            return;
        case ItemType::wavepacket13:
            decoders.emplace_back(std::in_place_type<Wavepacket13CodecV1>, false);
            return;
        default:
            v1 ? (void)decoders.emplace_back(std::in_place_type<ByteDecoderV1>, item.size)
               : (void)decoders.emplace_back(std::in_place_type<ByteCodecV2>, item.size, false);
    }
}

void check_output(std::size_t point_count, std::size_t length, std::size_t have) {
    if (length != 0 && point_count > have / length) {
        throw std::invalid_argument("point-wise chunk: output of " + std::to_string(have) +
                                    " bytes for " + std::to_string(point_count) + " records of " +
                                    std::to_string(length));
    }
}

}  // namespace

std::size_t record_length(std::span<const Item> items) {
    std::size_t length = 0;
    for (const Item& item : items) {
        length += item.size;
    }
    return length;
}

void check_pointwise_items(std::span<const Item> items) {
    if (items.empty()) {
        throw CorruptData("no items in the point record");
    }
    for (const Item& item : items) {
        const bool known = item.type == ItemType::point10 || item.type == ItemType::gpstime11 ||
                           item.type == ItemType::rgb12 || item.type == ItemType::byte ||
                           item.type == ItemType::wavepacket13;
        const bool version_ok = item.type == ItemType::wavepacket13
                                    ? item.version == 1
                                    : (item.version == 1 || item.version == 2);
        if (!known || !version_ok) {
            throw CorruptData("item " + describe(item) + " is not a point-wise item we decode");
        }
        const std::uint16_t size = fixed_size(item.type);
        if ((size != 0 && item.size != size) || item.size == 0) {
            throw CorruptData("item " + describe(item) + " has the wrong size");
        }
    }
}

struct PointwiseChunkDecoder::State {
    std::vector<Item> items;
    std::span<const std::uint8_t> bytes;
    std::size_t length = 0;
    std::size_t decoded = 0;
    std::vector<ItemDecoder> decoders;
    ArithmeticDecoder dec{{}};

    /// The first record, raw; then the item decoders start from it.
    void first(std::uint8_t* out) {
        if (bytes.size() < length) {
            throw CorruptData("chunk of " + std::to_string(bytes.size()) +
                              " bytes is shorter than its first record (" + std::to_string(length) +
                              " bytes)");
        }
        std::memcpy(out, bytes.data(), length);
        decoders.reserve(items.size());
        std::size_t at = 0;
        for (const Item& item : items) {
            emplace_decoder(decoders, item);
            std::visit([&](auto& d) { d.init(bytes.data() + at); }, decoders.back());
            at += item.size;
        }
    }

    void next(std::uint8_t* record) {
        if (decoded == 1) {
            dec = ArithmeticDecoder(bytes.subspan(length));
            dec.init();
        }
        for (std::size_t i = 0; i < items.size(); ++i) {
            std::visit([&](auto& d) { d.decode(dec, record); }, decoders[i]);
            record += items[i].size;
        }
    }
};

PointwiseChunkDecoder::PointwiseChunkDecoder(std::span<const Item> items,
                                             std::span<const std::uint8_t> bytes)
    : state_(std::make_unique<State>()) {
    check_pointwise_items(items);
    state_->items.assign(items.begin(), items.end());
    state_->bytes = bytes;
    state_->length = laz::record_length(items);
}

PointwiseChunkDecoder::~PointwiseChunkDecoder() = default;
PointwiseChunkDecoder::PointwiseChunkDecoder(PointwiseChunkDecoder&&) noexcept = default;
PointwiseChunkDecoder& PointwiseChunkDecoder::operator=(PointwiseChunkDecoder&&) noexcept = default;

std::size_t PointwiseChunkDecoder::record_length() const {
    return state_->length;
}
std::size_t PointwiseChunkDecoder::decoded() const {
    return state_->decoded;
}

void PointwiseChunkDecoder::decode(std::size_t count, std::span<std::uint8_t> out) {
    State& s = *state_;
    check_output(count, s.length, out.size());
    for (std::size_t p = 0; p < count; ++p) {
        std::uint8_t* record = out.data() + p * s.length;
        if (s.decoded == 0) {
            s.first(record);
        } else {
            s.next(record);
        }
        ++s.decoded;
    }
}

void decode_pointwise_chunk(std::span<const Item> items, std::span<const std::uint8_t> bytes,
                            std::size_t point_count, std::span<std::uint8_t> out) {
    PointwiseChunkDecoder decoder(items, bytes);
    decoder.decode(point_count, out);
}

void encode_pointwise_chunk(std::span<const Item> items, std::span<const std::uint8_t> records,
                            std::size_t point_count, std::vector<std::uint8_t>& out) {
    for (const Item& item : items) {
        if (item.version != (item.type == ItemType::wavepacket13 ? 1 : 2)) {
            throw std::invalid_argument("point-wise encoder: no encoder for item " +
                                        describe(item));
        }
    }
    check_pointwise_items(items);
    const std::size_t length = record_length(items);
    check_output(point_count, length, records.size());
    if (point_count == 0) {
        return;
    }
    out.insert(out.end(), records.begin(), records.begin() + static_cast<std::ptrdiff_t>(length));
    std::vector<ItemEncoder> encoders;
    encoders.reserve(items.size());
    std::size_t at = 0;
    for (const Item& item : items) {
        if (item.type == ItemType::point10) {
            encoders.emplace_back(std::in_place_type<Point10CodecV2>, true);
        } else if (item.type == ItemType::gpstime11) {
            encoders.emplace_back(std::in_place_type<Gpstime11CodecV2>, true);
        } else if (item.type == ItemType::rgb12) {
            encoders.emplace_back(std::in_place_type<Rgb12CodecV2>, true);
        } else if (item.type == ItemType::wavepacket13) {
            encoders.emplace_back(std::in_place_type<Wavepacket13CodecV1>, true);
        } else {
            encoders.emplace_back(std::in_place_type<ByteCodecV2>, item.size, true);
        }
        std::visit([&](auto& e) { e.init(records.data() + at); }, encoders.back());
        at += item.size;
    }
    ArithmeticEncoder enc(out);
    for (std::size_t p = 1; p < point_count; ++p) {
        const std::uint8_t* record = records.data() + p * length;
        for (std::size_t i = 0; i < items.size(); ++i) {
            std::visit([&](auto& e) { e.encode(enc, record); }, encoders[i]);
            record += items[i].size;
        }
    }
    enc.done();
}

}  // namespace beamtrace::laz
