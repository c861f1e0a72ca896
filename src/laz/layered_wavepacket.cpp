#include "laz/layered_wavepacket.hpp"
#include "laz/item_bytes.hpp"
#include "laz/layered_item_models.hpp"

#include <cstring>

namespace beamtrace::laz {

using wavepacket14::kOffset;
using wavepacket14::kReturnPoint;
using wavepacket14::kSize;
using wavepacket14::kXyz;

struct WavePacket14Decoder::Context : wavepacket14::ChannelModels {
    static_assert(kBytes == wavepacket14::kItemBytes);
    Context() : ChannelModels(false) {}
};

WavePacket14Decoder::WavePacket14Decoder(const std::uint8_t* first,
                                         std::span<const std::uint8_t> layer, unsigned channel)
    : layer_(layer), current_(channel) {
    std::array<std::uint8_t, kBytes> item{};
    std::memcpy(item.data(), first, kBytes);
    start_context(channel, item);
}

WavePacket14Decoder::~WavePacket14Decoder() = default;

void WavePacket14Decoder::start_context(unsigned channel,
                                        const std::array<std::uint8_t, kBytes>& from) {
    auto c = std::make_unique<Context>();
    c->last = from;
    contexts_[channel] = std::move(c);
}

void WavePacket14Decoder::decode(std::uint8_t* out, unsigned channel) {
    std::array<std::uint8_t, kBytes>* last = &contexts_[current_]->last;
    if (channel != current_) {
        current_ = channel;
        if (!contexts_[channel]) {
            start_context(channel, *last);
            last = &contexts_[channel]->last;
        }
    }
    if (layer_.coded) {
        Context& c = *contexts_[current_];
        ArithmeticDecoder& dec = layer_.decoder;
        std::uint8_t* l = last->data();
        const std::uint8_t index = static_cast<std::uint8_t>(dec.decode_symbol(c.packet_index));
        c.last_offset_code = dec.decode_symbol(c.offset_code[c.last_offset_code]);
        std::uint64_t offset = load<std::uint64_t>(l + kOffset);
        if (c.last_offset_code == 1) {
            offset += load<std::uint32_t>(l + kSize);
        } else if (c.last_offset_code == 2) {
            c.last_offset_diff = c.offset_diff.decompress(dec, c.last_offset_diff);
            offset += static_cast<std::uint64_t>(static_cast<std::int64_t>(c.last_offset_diff));
        } else if (c.last_offset_code == 3) {
            offset = dec.read_int64();
        }
        const std::int32_t size = c.packet_size.decompress(dec, load<std::int32_t>(l + kSize));
        const std::int32_t point =
            c.return_point.decompress(dec, load<std::int32_t>(l + kReturnPoint));
        std::array<std::int32_t, 3> d{};
        for (std::uint32_t k = 0; k < 3; ++k) {
            d[k] = c.xyz.decompress(dec, load<std::int32_t>(l + kXyz + 4 * k), k);
        }
        l[0] = index;
        store(l + kOffset, offset);
        store(l + kSize, size);
        store(l + kReturnPoint, point);
        for (std::size_t k = 0; k < 3; ++k) {
            store(l + kXyz + 4 * k, d[k]);
        }
    }
    std::memcpy(out, last->data(), kBytes);
}

}  // namespace beamtrace::laz
