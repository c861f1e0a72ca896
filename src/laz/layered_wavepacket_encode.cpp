#include "laz/layered_wavepacket_encode.hpp"

#include <cstring>

#include "laz/arithmetic_model.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/item_bytes.hpp"

namespace beamtrace::laz {

namespace {

// Byte offsets of the fields in the item.
constexpr std::size_t kOffset = 1;
constexpr std::size_t kSize = 9;
constexpr std::size_t kReturnPoint = 13;
constexpr std::size_t kXyz = 17;

}  // namespace

struct WavePacket14Encoder::Context {
    std::array<std::uint8_t, kBytes> last{};
    std::int32_t last_offset_diff = 0;
    std::uint32_t last_offset_code = 0;
    ArithmeticModel packet_index{256, true};
    std::array<ArithmeticModel, 4> offset_code{ArithmeticModel(4, true), ArithmeticModel(4, true),
                                               ArithmeticModel(4, true), ArithmeticModel(4, true)};
    IntegerCompressor offset_diff{32};
    IntegerCompressor packet_size{32};
    IntegerCompressor return_point{32};
    IntegerCompressor xyz{32, 3};

    Context() {
        packet_index.init();
        for (ArithmeticModel& m : offset_code) {
            m.init();
        }
        offset_diff.init_compressor();
        packet_size.init_compressor();
        return_point.init_compressor();
        xyz.init_compressor();
    }
};

WavePacket14Encoder::WavePacket14Encoder(const std::uint8_t* first, unsigned channel)
    : current_(channel) {
    std::array<std::uint8_t, kBytes> item{};
    std::memcpy(item.data(), first, kBytes);
    start_context(channel, item);
}

WavePacket14Encoder::~WavePacket14Encoder() = default;

void WavePacket14Encoder::start_context(unsigned channel,
                                        const std::array<std::uint8_t, kBytes>& from) {
    auto c = std::make_unique<Context>();
    c->last = from;
    contexts_[channel] = std::move(c);
}

void WavePacket14Encoder::encode_offset(Context& c, const std::uint8_t* last,
                                        const std::uint8_t* item) {
    ArithmeticEncoder& enc = layer_.encoder;
    const std::uint64_t offset = load<std::uint64_t>(item + kOffset);
    const auto d64 = static_cast<std::int64_t>(offset - load<std::uint64_t>(last + kOffset));
    const auto d32 = static_cast<std::int32_t>(d64);
    std::uint32_t code = 3;
    if (d64 == d32) {
        code = d32 == 0 ? 0U : d32 == load<std::int32_t>(last + kSize) ? 1U : 2U;
    }
    enc.encode_symbol(c.offset_code[c.last_offset_code], code);
    c.last_offset_code = code;
    if (code == 2) {
        c.offset_diff.compress(enc, c.last_offset_diff, d32);
        c.last_offset_diff = d32;
    } else if (code == 3) {
        enc.write_int64(offset);
    }
}

void WavePacket14Encoder::encode(const std::uint8_t* item, unsigned channel) {
    std::array<std::uint8_t, kBytes>* last = &contexts_[current_]->last;
    if (channel != current_) {
        current_ = channel;
        if (!contexts_[channel]) {
            start_context(channel, *last);
            last = &contexts_[channel]->last;
        }
    }
    Context& c = *contexts_[current_];
    std::uint8_t* l = last->data();
    layer_.changed |= std::memcmp(item, l, kBytes) != 0;
    ArithmeticEncoder& enc = layer_.encoder;
    enc.encode_symbol(c.packet_index, item[0]);
    encode_offset(c, l, item);
    c.packet_size.compress(enc, load<std::int32_t>(l + kSize), load<std::int32_t>(item + kSize));
    c.return_point.compress(enc, load<std::int32_t>(l + kReturnPoint),
                            load<std::int32_t>(item + kReturnPoint));
    for (std::uint32_t k = 0; k < 3; ++k) {
        c.xyz.compress(enc, load<std::int32_t>(l + kXyz + 4 * k),
                       load<std::int32_t>(item + kXyz + 4 * k), k);
    }
    std::memcpy(l, item, kBytes);
}

void WavePacket14Encoder::finish(std::vector<std::span<const std::uint8_t>>& layers) {
    layers.push_back(layer_.finish());
}

}  // namespace beamtrace::laz
