#include "laz/laz_vlr.hpp"

#include <cstring>
#include <string>

namespace beamtrace::laz {

namespace {

constexpr std::size_t kFixedBytes = 34;
constexpr std::size_t kItemBytes = 6;

template <typename T>
[[nodiscard]] T load(const std::uint8_t* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
}

[[noreturn]] void corrupt(const std::string& what) {
    throw CorruptData("LASzip VLR: " + what);
}

/// The fixed size of an item type, 0 for the variable-size extra bytes, -1 when unknown.
[[nodiscard]] int fixed_size(ItemType type) {
    switch (type) {
        case ItemType::byte:
        case ItemType::byte14:
            return 0;
        case ItemType::point10:
            return 20;
        case ItemType::gpstime11:
            return 8;
        case ItemType::rgb12:
        case ItemType::rgb14:
            return 6;
        case ItemType::wavepacket13:
        case ItemType::wavepacket14:
            return 29;
        case ItemType::point14:
            return 30;
        case ItemType::rgbnir14:
            return 8;
    }
    return -1;
}

[[nodiscard]] bool is_layered(ItemType type) {
    return type == ItemType::point14 || type == ItemType::rgb14 || type == ItemType::rgbnir14 ||
           type == ItemType::wavepacket14 || type == ItemType::byte14;
}

void check_item(const Item& item, std::size_t index, bool layered) {
    const std::string where =
        "item " + std::to_string(index + 1) + " (" + item_name(item.type) + ")";
    const int size = fixed_size(item.type);
    if (size < 0) {
        corrupt(where + ": unknown item type " + std::to_string(static_cast<unsigned>(item.type)));
    }
    if (size > 0 && item.size != size) {
        corrupt(where + ": size " + std::to_string(item.size) + ", expected " +
                std::to_string(size));
    }
    if (size == 0 && item.size == 0) {
        corrupt(where + ": extra bytes item of size 0");
    }
    if (is_layered(item.type) != layered) {
        corrupt(where + (layered ? ": a point-wise item in a layered (compressor 3) file"
                                 : ": a layered item in a point-wise file"));
    }
    const bool version_ok = layered ? item.version == 3 : (item.version == 1 || item.version == 2);
    if (!version_ok) {
        corrupt(where + ": unsupported item version " + std::to_string(item.version));
    }
}

/// The items a record of `format` must start with, in order.
[[nodiscard]] std::vector<ItemType> expected_items(int format) {
    switch (format) {
        case 0:
            return {ItemType::point10};
        case 1:
            return {ItemType::point10, ItemType::gpstime11};
        case 2:
            return {ItemType::point10, ItemType::rgb12};
        case 3:
            return {ItemType::point10, ItemType::gpstime11, ItemType::rgb12};
        case 4:
            return {ItemType::point10, ItemType::gpstime11, ItemType::wavepacket13};
        case 5:
            return {ItemType::point10, ItemType::gpstime11, ItemType::rgb12,
                    ItemType::wavepacket13};
        case 6:
            return {ItemType::point14};
        case 7:
            return {ItemType::point14, ItemType::rgb14};
        case 8:
            return {ItemType::point14, ItemType::rgbnir14};
        case 9:
            return {ItemType::point14, ItemType::wavepacket14};
        default:
            return {ItemType::point14, ItemType::rgbnir14, ItemType::wavepacket14};
    }
}

void check_items_match(const LazVlr& vlr, int format, std::size_t record_length) {
    const std::vector<ItemType> expected = expected_items(format);
    const auto extra = format <= 5 ? ItemType::byte : ItemType::byte14;
    for (std::size_t i = 0; i < vlr.items.size(); ++i) {
        const ItemType want = i < expected.size() ? expected[i] : extra;
        if (vlr.items[i].type != want) {
            corrupt("item " + std::to_string(i + 1) + " is " + item_name(vlr.items[i].type) +
                    " where point format " + std::to_string(format) + " needs " + item_name(want));
        }
    }
    if (vlr.items.size() < expected.size()) {
        corrupt(std::to_string(vlr.items.size()) + " items, point format " +
                std::to_string(format) + " needs at least " + std::to_string(expected.size()));
    }
    if (vlr.record_length() != record_length) {
        corrupt("the items make up " + std::to_string(vlr.record_length()) +
                "-byte records, the header says " + std::to_string(record_length));
    }
}

}  // namespace

std::size_t LazVlr::record_length() const {
    std::size_t n = 0;
    for (const Item& item : items) {
        n += item.size;
    }
    return n;
}

LazVlr parse_laz_vlr(std::span<const std::uint8_t> data, int point_format,
                     std::size_t record_length) {
    if (data.size() < kFixedBytes) {
        corrupt(std::to_string(data.size()) + " bytes, shorter than its " +
                std::to_string(kFixedBytes) + "-byte fixed part");
    }
    const std::uint8_t* p = data.data();
    LazVlr v;
    const auto compressor = load<std::uint16_t>(p);
    if (compressor > 3) {
        corrupt("unknown compressor " + std::to_string(compressor));
    }
    v.compressor = static_cast<Compressor>(compressor);
    v.coder = load<std::uint16_t>(p + 2);
    if (v.coder != 0) {
        corrupt("unknown coder " + std::to_string(v.coder) + " (only 0, arithmetic, exists)");
    }
    v.version_major = p[4];
    v.version_minor = p[5];
    v.version_revision = load<std::uint16_t>(p + 6);
    v.options = load<std::uint32_t>(p + 8);
    v.chunk_size = load<std::uint32_t>(p + 12);
    v.special_evlr_count = load<std::int64_t>(p + 16);
    v.special_evlr_offset = load<std::int64_t>(p + 24);
    const auto count = load<std::uint16_t>(p + 32);
    if (data.size() != kFixedBytes + kItemBytes * count) {
        corrupt(std::to_string(count) + " items need " +
                std::to_string(kFixedBytes + kItemBytes * count) + " bytes, the record has " +
                std::to_string(data.size()));
    }
    if (v.compressor == Compressor::none) {
        corrupt("compressor 0 (none) in a compressed file");
    }
    if (v.chunk_size == 0 && v.compressor != Compressor::pointwise) {
        v.chunk_size = kVariableChunkSize;  // as LASzip reads it: chunk sizes in the table
    }
    const bool layered = v.compressor == Compressor::layered_chunked;
    if (layered != (point_format >= 6)) {
        corrupt("compressor " + std::to_string(compressor) + " cannot code point format " +
                std::to_string(point_format));
    }
    v.items.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint8_t* q = p + kFixedBytes + kItemBytes * i;
        const Item item{static_cast<ItemType>(load<std::uint16_t>(q)), load<std::uint16_t>(q + 2),
                        load<std::uint16_t>(q + 4)};
        check_item(item, i, layered);
        v.items.push_back(item);
    }
    check_items_match(v, point_format, record_length);
    return v;
}

}  // namespace beamtrace::laz
