#include "laz/laz_items.hpp"

namespace beamtrace::laz {

std::string item_name(ItemType type) {
    switch (type) {
        case ItemType::byte:
            return "BYTE";
        case ItemType::point10:
            return "POINT10";
        case ItemType::gpstime11:
            return "GPSTIME11";
        case ItemType::rgb12:
            return "RGB12";
        case ItemType::wavepacket13:
            return "WAVEPACKET13";
        case ItemType::point14:
            return "POINT14";
        case ItemType::rgb14:
            return "RGB14";
        case ItemType::rgbnir14:
            return "RGBNIR14";
        case ItemType::wavepacket14:
            return "WAVEPACKET14";
        case ItemType::byte14:
            return "BYTE14";
    }
    return "item " + std::to_string(static_cast<unsigned>(type));
}

}  // namespace beamtrace::laz
