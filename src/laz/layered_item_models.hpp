// The models of the layered RGB14 and WAVEPACKET14 items (version 3) for one scanner channel:
// the same in the decoder and the encoder, each initialising them for its side.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "laz/arithmetic_model.hpp"
#include "laz/integer_compressor.hpp"

namespace beamtrace::laz {

namespace rgb14 {

/// The last colour of a channel and the models that code the next one.
struct ChannelModels {
    explicit ChannelModels(bool compress) : compress_side(compress) {
        byte_used.init();
        for (ArithmeticModel& m : diff) {
            m.init();
        }
        nir_used.init();
        for (ArithmeticModel& m : nir_diff) {
            m.init();
        }
    }

    bool compress_side;
    std::array<std::uint16_t, 4> last{};  ///< red, green, blue, NIR
    ArithmeticModel byte_used{128, compress_side};
    std::array<ArithmeticModel, 6> diff{
        ArithmeticModel(256, compress_side), ArithmeticModel(256, compress_side),
        ArithmeticModel(256, compress_side), ArithmeticModel(256, compress_side),
        ArithmeticModel(256, compress_side), ArithmeticModel(256, compress_side)};
    ArithmeticModel nir_used{4, compress_side};
    std::array<ArithmeticModel, 2> nir_diff{ArithmeticModel(256, compress_side),
                                            ArithmeticModel(256, compress_side)};
};

}  // namespace rgb14

namespace wavepacket14 {

// Byte offsets of the fields in the item.
inline constexpr std::size_t kOffset = 1;
inline constexpr std::size_t kSize = 9;
inline constexpr std::size_t kReturnPoint = 13;
inline constexpr std::size_t kXyz = 17;
inline constexpr std::size_t kItemBytes = 29;

/// The last packet of a channel and the models that code the next one.
struct ChannelModels {
    explicit ChannelModels(bool compress) : compress_side(compress) {
        packet_index.init();
        for (ArithmeticModel& m : offset_code) {
            m.init();
        }
        for (IntegerCompressor* ic : {&offset_diff, &packet_size, &return_point, &xyz}) {
            compress ? ic->init_compressor() : ic->init_decompressor();
        }
    }

    bool compress_side;
    std::array<std::uint8_t, kItemBytes> last{};
    std::int32_t last_offset_diff = 0;
    std::uint32_t last_offset_code = 0;
    ArithmeticModel packet_index{256, compress_side};
    std::array<ArithmeticModel, 4> offset_code{
        ArithmeticModel(4, compress_side), ArithmeticModel(4, compress_side),
        ArithmeticModel(4, compress_side), ArithmeticModel(4, compress_side)};
    IntegerCompressor offset_diff{32};
    IntegerCompressor packet_size{32};
    IntegerCompressor return_point{32};
    IntegerCompressor xyz{32, 3};
};

}  // namespace wavepacket14

}  // namespace beamtrace::laz
