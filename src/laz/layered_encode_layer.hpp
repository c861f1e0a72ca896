// One layer of a layered (LASzip 3) chunk being encoded: its own byte stream and range coder,
// and whether any value it codes differed from its predecessor. LASzip ends every layer's
// stream but writes a layer whose values never changed as 0 bytes (the decoder then keeps the
// chunk's first value, layered_layer.hpp); finish() does the same.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "laz/arithmetic_encoder.hpp"

namespace beamtrace::laz {

struct EncodeLayer {
    EncodeLayer() : encoder(bytes) {}
    EncodeLayer(const EncodeLayer&) = delete;
    EncodeLayer& operator=(const EncodeLayer&) = delete;
    EncodeLayer(EncodeLayer&&) = delete;
    EncodeLayer& operator=(EncodeLayer&&) = delete;
    ~EncodeLayer() = default;

    /// Ends the stream; returns its bytes, or none when nothing changed (and !`always`).
    [[nodiscard]] std::span<const std::uint8_t> finish(bool always = false) {
        encoder.done();
        if (!changed && !always) {
            return {};
        }
        return bytes;
    }

    std::vector<std::uint8_t> bytes;  ///< declared before the encoder, which appends to it
    ArithmeticEncoder encoder;
    bool changed = false;
};

/// The byte symbol of `value - last`, modulo 256 (the format's U8 fold).
[[nodiscard]] inline std::uint32_t fold_diff(std::uint32_t value, std::uint32_t last) {
    return (value - last) & 0xFFU;
}

}  // namespace beamtrace::laz
