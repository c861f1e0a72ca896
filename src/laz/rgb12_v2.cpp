// RGB12 version 2. A 7-bit mask says which of the six colour bytes changed (bit 2c: the low
// byte of channel c, 2c + 1 its high byte) and whether the point is not grey (bit 6; a grey
// point codes red only). Green is predicted from red's change, blue from the mean change of
// red and green, each byte separately.
#include <algorithm>

#include "laz/items_v2.hpp"

namespace beamtrace::laz {
namespace {

std::int32_t clamp_u8(std::int32_t v) {
    return std::clamp(v, 0, 255);
}
std::uint32_t fold_u8(std::int32_t v) {
    return static_cast<std::uint32_t>(v) & 0xFFU;
}
std::int32_t low(std::uint16_t v) {
    return v & 0xFF;
}
std::int32_t high(std::uint16_t v) {
    return v >> 8;
}

}  // namespace

Rgb12CodecV2::Rgb12CodecV2(bool compress)
    : used_(128, compress), diff_{ArithmeticModel(256, compress), ArithmeticModel(256, compress),
                                  ArithmeticModel(256, compress), ArithmeticModel(256, compress),
                                  ArithmeticModel(256, compress), ArithmeticModel(256, compress)} {}

void Rgb12CodecV2::init(const std::uint8_t* item) {
    used_.init();
    for (ArithmeticModel& m : diff_) {
        m.init();
    }
    last_ = {load_u16(item), load_u16(item + 2), load_u16(item + 4)};
}

void Rgb12CodecV2::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    const std::uint32_t sym = dec.decode_symbol(used_);
    // One byte: the previous value, or the prediction plus the coded correction.
    auto byte = [&](unsigned bit, std::int32_t previous, std::int32_t prediction) {
        if ((sym & (1U << bit)) == 0) {
            return previous;
        }
        return static_cast<std::int32_t>(
            fold_u8(static_cast<std::int32_t>(dec.decode_symbol(diff_[bit])) + prediction));
    };
    std::array<std::uint16_t, 3> rgb{};
    const std::int32_t r_lo = byte(0, low(last_[0]), low(last_[0]));
    const std::int32_t r_hi = byte(1, high(last_[0]), high(last_[0]));
    rgb[0] = static_cast<std::uint16_t>(r_lo | (r_hi << 8));
    if ((sym & (1U << 6)) != 0) {
        std::int32_t d = r_lo - low(last_[0]);
        const std::int32_t g_lo = byte(2, low(last_[1]), clamp_u8(d + low(last_[1])));
        d = (d + g_lo - low(last_[1])) / 2;
        const std::int32_t b_lo = byte(4, low(last_[2]), clamp_u8(d + low(last_[2])));
        d = r_hi - high(last_[0]);
        const std::int32_t g_hi = byte(3, high(last_[1]), clamp_u8(d + high(last_[1])));
        d = (d + g_hi - high(last_[1])) / 2;
        const std::int32_t b_hi = byte(5, high(last_[2]), clamp_u8(d + high(last_[2])));
        rgb[1] = static_cast<std::uint16_t>(g_lo | (g_hi << 8));
        rgb[2] = static_cast<std::uint16_t>(b_lo | (b_hi << 8));
    } else {
        rgb[1] = rgb[0];
        rgb[2] = rgb[0];
    }
    for (std::size_t c = 0; c < 3; ++c) {
        store_u16(item + 2 * c, rgb[c]);
    }
    last_ = rgb;
}

void Rgb12CodecV2::encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
    const std::array<std::uint16_t, 3> rgb{load_u16(item), load_u16(item + 2), load_u16(item + 4)};
    std::uint32_t sym = 0;
    for (unsigned c = 0; c < 3; ++c) {
        sym |= (low(rgb[c]) != low(last_[c]) ? 1U : 0U) << (2 * c);
        sym |= (high(rgb[c]) != high(last_[c]) ? 1U : 0U) << (2 * c + 1);
    }
    if (rgb[1] != rgb[0] || rgb[2] != rgb[0]) {
        sym |= 1U << 6;
    }
    enc.encode_symbol(used_, sym);
    auto byte = [&](unsigned bit, std::int32_t value, std::int32_t prediction) {
        if ((sym & (1U << bit)) != 0) {
            enc.encode_symbol(diff_[bit], fold_u8(value - prediction));
        }
    };
    byte(0, low(rgb[0]), low(last_[0]));
    byte(1, high(rgb[0]), high(last_[0]));
    if ((sym & (1U << 6)) != 0) {
        std::int32_t d = low(rgb[0]) - low(last_[0]);
        byte(2, low(rgb[1]), clamp_u8(d + low(last_[1])));
        d = (d + low(rgb[1]) - low(last_[1])) / 2;
        byte(4, low(rgb[2]), clamp_u8(d + low(last_[2])));
        d = high(rgb[0]) - high(last_[0]);
        byte(3, high(rgb[1]), clamp_u8(d + high(last_[1])));
        d = (d + high(rgb[1]) - high(last_[1])) / 2;
        byte(5, high(rgb[2]), clamp_u8(d + high(last_[2])));
    }
    last_ = rgb;
}

}  // namespace beamtrace::laz
