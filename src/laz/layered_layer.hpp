// One layer of a layered (LASzip 3) chunk: its bytes and whether the chunk codes it at all.
//
// A layer of 0 bytes means "this field does not change within the chunk": the item keeps the
// value of the chunk's first record. Otherwise the layer is one arithmetic-coded stream.
#pragma once

#include <cstdint>
#include <span>

#include "laz/arithmetic_decoder.hpp"

namespace beamtrace::laz {

struct Layer {
    explicit Layer(std::span<const std::uint8_t> bytes) : decoder(bytes), coded(!bytes.empty()) {
        if (coded) {
            decoder.init();
        }
    }

    ArithmeticDecoder decoder;
    bool coded;
};

/// Adds `corr` (a byte symbol) to the last byte value, modulo 256 (the format's U8 fold).
[[nodiscard]] inline std::uint8_t fold_byte(std::uint32_t corr, std::uint32_t last) {
    return static_cast<std::uint8_t>((corr + last) & 0xFFU);
}

}  // namespace beamtrace::laz
