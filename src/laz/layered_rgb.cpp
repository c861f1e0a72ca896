#include "laz/layered_rgb.hpp"

#include <algorithm>
#include <cstring>

#include "laz/layered_item_models.hpp"

namespace beamtrace::laz {

namespace {

[[nodiscard]] std::uint32_t low(std::uint16_t v) {
    return v & 0xFFU;
}
[[nodiscard]] std::uint32_t high(std::uint16_t v) {
    return v >> 8U;
}

/// The last byte plus a predicted change, clamped to a byte.
[[nodiscard]] std::uint32_t clamp_byte(std::int32_t v) {
    return static_cast<std::uint32_t>(std::clamp(v, 0, 255));
}

}  // namespace

struct Rgb14Decoder::Context : rgb14::ChannelModels {
    Context() : ChannelModels(false) {}
};

Rgb14Decoder::Rgb14Decoder(const std::uint8_t* first, bool nir, std::span<const std::uint8_t> rgb,
                           std::span<const std::uint8_t> nir_layer, unsigned channel)
    : rgb_(rgb) {
    std::array<std::uint16_t, 4> colour{};
    std::memcpy(colour.data(), first, nir ? 8 : 6);
    if (nir) {
        nir_.emplace(nir_layer);
    }
    current_ = channel;
    start_context(channel, colour);
}

Rgb14Decoder::~Rgb14Decoder() = default;

void Rgb14Decoder::start_context(unsigned channel, const std::array<std::uint16_t, 4>& from) {
    auto c = std::make_unique<Context>();
    c->last = from;
    contexts_[channel] = std::move(c);
}

void Rgb14Decoder::decode(std::uint8_t* out, unsigned channel) {
    std::array<std::uint16_t, 4>* last = &contexts_[current_]->last;
    if (channel != current_) {
        current_ = channel;
        if (!contexts_[channel]) {
            start_context(channel, *last);
            last = &contexts_[channel]->last;
        }
    }
    Context& c = *contexts_[current_];
    if (rgb_.coded) {
        decode_rgb(c, *last);
    }
    std::memcpy(out, last->data(), 6);
    if (nir_) {
        if (nir_->coded) {
            decode_nir(c, *last);
        }
        std::memcpy(out + 6, &(*last)[3], 2);
    }
}

void Rgb14Decoder::decode_rgb(Context& c, std::array<std::uint16_t, 4>& last) {
    ArithmeticDecoder& dec = rgb_.decoder;
    const std::uint32_t sym = dec.decode_symbol(c.byte_used);
    std::array<std::uint32_t, 3> lo{low(last[0]), low(last[1]), low(last[2])};
    std::array<std::uint32_t, 3> hi{high(last[0]), high(last[1]), high(last[2])};
    const std::array<std::uint32_t, 3> lo0 = lo;
    const std::array<std::uint32_t, 3> hi0 = hi;
    if ((sym & 1U) != 0) {
        lo[0] = fold_byte(dec.decode_symbol(c.diff[0]), lo0[0]);
    }
    if ((sym & 2U) != 0) {
        hi[0] = fold_byte(dec.decode_symbol(c.diff[1]), hi0[0]);
    }
    if ((sym & (1U << 6)) != 0) {
        std::int32_t d = static_cast<std::int32_t>(lo[0]) - static_cast<std::int32_t>(lo0[0]);
        if ((sym & (1U << 2)) != 0) {
            lo[1] = fold_byte(dec.decode_symbol(c.diff[2]),
                              clamp_byte(d + static_cast<std::int32_t>(lo0[1])));
        }
        if ((sym & (1U << 4)) != 0) {
            d = (d + static_cast<std::int32_t>(lo[1]) - static_cast<std::int32_t>(lo0[1])) / 2;
            lo[2] = fold_byte(dec.decode_symbol(c.diff[4]),
                              clamp_byte(d + static_cast<std::int32_t>(lo0[2])));
        }
        d = static_cast<std::int32_t>(hi[0]) - static_cast<std::int32_t>(hi0[0]);
        if ((sym & (1U << 3)) != 0) {
            hi[1] = fold_byte(dec.decode_symbol(c.diff[3]),
                              clamp_byte(d + static_cast<std::int32_t>(hi0[1])));
        }
        if ((sym & (1U << 5)) != 0) {
            d = (d + static_cast<std::int32_t>(hi[1]) - static_cast<std::int32_t>(hi0[1])) / 2;
            hi[2] = fold_byte(dec.decode_symbol(c.diff[5]),
                              clamp_byte(d + static_cast<std::int32_t>(hi0[2])));
        }
    } else {
        lo[1] = lo[2] = lo[0];
        hi[1] = hi[2] = hi[0];
    }
    for (std::size_t k = 0; k < 3; ++k) {
        last[k] = static_cast<std::uint16_t>(lo[k] | (hi[k] << 8U));
    }
}

void Rgb14Decoder::decode_nir(Context& c, std::array<std::uint16_t, 4>& last) {
    ArithmeticDecoder& dec = nir_->decoder;
    const std::uint32_t sym = dec.decode_symbol(c.nir_used);
    std::uint32_t lo = low(last[3]);
    std::uint32_t hi = high(last[3]);
    if ((sym & 1U) != 0) {
        lo = fold_byte(dec.decode_symbol(c.nir_diff[0]), lo);
    }
    if ((sym & 2U) != 0) {
        hi = fold_byte(dec.decode_symbol(c.nir_diff[1]), hi);
    }
    last[3] = static_cast<std::uint16_t>(lo | (hi << 8U));
}

}  // namespace beamtrace::laz
