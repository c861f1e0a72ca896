#include "laz/layered_wavepacket_encode.hpp"

#include <cstring>

#include "laz/arithmetic_model.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/item_bytes.hpp"
#include "laz/layered_item_models.hpp"

namespace beamtrace::laz {

using wavepacket14::kOffset;
using wavepacket14::kReturnPoint;
using wavepacket14::kSize;
using wavepacket14::kXyz;

struct WavePacket14Encoder::Context : wavepacket14::ChannelModels {
    static_assert(kBytes == wavepacket14::kItemBytes);
    Context() : ChannelModels(true) {}
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
