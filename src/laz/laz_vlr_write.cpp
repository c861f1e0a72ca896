// laz_vlr_for and serialize_laz_vlr: the LASzip VLR that LASzip 3.4 writes for a point format.
//
// The items are LASzip's for the format (LASzip::setup): POINT10 [GPSTIME11] [RGB12]
// [WAVEPACKET13] [BYTE] for formats 0-5, POINT14 [RGB14 | RGBNIR14] [WAVEPACKET14] [BYTE14] for
// 6-10, the extra bytes of the record as one BYTE/BYTE14 item. Versions as LASzip requests them
// (request_version(2), then 3 for the layered items of LAS 1.4): 2 for the point-wise items, 1
// for WAVEPACKET13, 3 for the layered ones. The library version is 3.4 r3 (LASzip 3.4.3, the
// release most LAZ files come from), options 0, no special EVLRs (-1, -1).
#include <stdexcept>
#include <string>

#include "laz/item_bytes.hpp"
#include "laz/laz_encode.hpp"

namespace beamtrace::laz {

namespace {

constexpr std::uint8_t kVersionMajor = 3;
constexpr std::uint8_t kVersionMinor = 4;
constexpr std::uint16_t kVersionRevision = 3;

/// The items of `format` before its extra bytes, with the record bytes they cover.
[[nodiscard]] std::vector<Item> core_items(int format) {
    const Item point10{ItemType::point10, 20, 2};
    const Item gps{ItemType::gpstime11, 8, 2};
    const Item rgb12{ItemType::rgb12, 6, 2};
    const Item wave13{ItemType::wavepacket13, 29, 1};
    const Item point14{ItemType::point14, 30, 3};
    const Item rgb14{ItemType::rgb14, 6, 3};
    const Item nir14{ItemType::rgbnir14, 8, 3};
    const Item wave14{ItemType::wavepacket14, 29, 3};
    switch (format) {
        case 0:
            return {point10};
        case 1:
            return {point10, gps};
        case 2:
            return {point10, rgb12};
        case 3:
            return {point10, gps, rgb12};
        case 4:
            return {point10, gps, wave13};
        case 5:
            return {point10, gps, rgb12, wave13};
        case 6:
            return {point14};
        case 7:
            return {point14, rgb14};
        case 8:
            return {point14, nir14};
        case 9:
            return {point14, wave14};
        case 10:
            return {point14, nir14, wave14};
        default:
            throw std::invalid_argument("LASzip VLR: no point format " + std::to_string(format) +
                                        " (0-10)");
    }
}

}  // namespace

LazVlr laz_vlr_for(int point_format, std::size_t record_length, std::uint32_t chunk_size) {
    LazVlr vlr;
    vlr.items = core_items(point_format);
    const std::size_t core = vlr.record_length();
    if (record_length < core || record_length - core > 0xFFFFU) {
        throw std::invalid_argument("LASzip VLR: a record of " + std::to_string(record_length) +
                                    " bytes for point format " + std::to_string(point_format) +
                                    " (at least " + std::to_string(core) + ")");
    }
    const bool layered = point_format >= 6;
    if (record_length > core) {
        vlr.items.push_back({layered ? ItemType::byte14 : ItemType::byte,
                             static_cast<std::uint16_t>(record_length - core),
                             static_cast<std::uint16_t>(layered ? 3 : 2)});
    }
    vlr.compressor = layered ? Compressor::layered_chunked : Compressor::pointwise_chunked;
    vlr.coder = 0;
    vlr.version_major = kVersionMajor;
    vlr.version_minor = kVersionMinor;
    vlr.version_revision = kVersionRevision;
    vlr.options = 0;
    vlr.chunk_size = chunk_size;
    vlr.special_evlr_count = -1;
    vlr.special_evlr_offset = -1;
    return vlr;
}

std::vector<std::uint8_t> serialize_laz_vlr(const LazVlr& vlr) {
    if (vlr.items.size() > 0xFFFFU) {
        throw std::invalid_argument("LASzip VLR: " + std::to_string(vlr.items.size()) + " items");
    }
    std::vector<std::uint8_t> out(34 + 6 * vlr.items.size());
    std::uint8_t* p = out.data();
    store(p, static_cast<std::uint16_t>(vlr.compressor));
    store(p + 2, vlr.coder);
    p[4] = vlr.version_major;
    p[5] = vlr.version_minor;
    store(p + 6, vlr.version_revision);
    store(p + 8, vlr.options);
    store(p + 12, vlr.chunk_size);
    store(p + 16, vlr.special_evlr_count);
    store(p + 24, vlr.special_evlr_offset);
    store(p + 32, static_cast<std::uint16_t>(vlr.items.size()));
    for (std::size_t i = 0; i < vlr.items.size(); ++i) {
        std::uint8_t* q = p + 34 + 6 * i;
        store(q, static_cast<std::uint16_t>(vlr.items[i].type));
        store(q + 2, vlr.items[i].size);
        store(q + 4, vlr.items[i].version);
    }
    return out;
}

}  // namespace beamtrace::laz
