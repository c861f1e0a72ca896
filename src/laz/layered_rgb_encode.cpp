#include "laz/layered_rgb_encode.hpp"

#include <algorithm>
#include <cstring>

#include "laz/arithmetic_model.hpp"
#include "laz/layered_item_models.hpp"

namespace beamtrace::laz {

namespace {

[[nodiscard]] std::int32_t low(std::uint16_t v) {
    return v & 0xFF;
}
[[nodiscard]] std::int32_t high(std::uint16_t v) {
    return v >> 8U;
}

/// The byte symbol of `value - clamp(prediction)` (LASzip's U8_FOLD of the corrector).
[[nodiscard]] std::uint32_t corrector(std::int32_t value, std::int32_t prediction) {
    return fold_diff(static_cast<std::uint32_t>(value),
                     static_cast<std::uint32_t>(std::clamp(prediction, 0, 255)));
}

}  // namespace

struct Rgb14Encoder::Context : rgb14::ChannelModels {
    Context() : ChannelModels(true) {}
};

Rgb14Encoder::Rgb14Encoder(const std::uint8_t* first, bool nir, unsigned channel)
    : nir_(nir), current_(channel) {
    std::array<std::uint16_t, 4> colour{};
    std::memcpy(colour.data(), first, nir ? 8 : 6);
    start_context(channel, colour);
}

Rgb14Encoder::~Rgb14Encoder() = default;

void Rgb14Encoder::start_context(unsigned channel, const std::array<std::uint16_t, 4>& from) {
    auto c = std::make_unique<Context>();
    c->last = from;
    contexts_[channel] = std::move(c);
}

void Rgb14Encoder::encode(const std::uint8_t* item, unsigned channel) {
    std::array<std::uint16_t, 4>* last = &contexts_[current_]->last;
    if (channel != current_) {
        current_ = channel;
        if (!contexts_[channel]) {
            start_context(channel, *last);
            last = &contexts_[channel]->last;
        }
    }
    Context& c = *contexts_[current_];
    std::array<std::uint16_t, 4> now{};
    std::memcpy(now.data(), item, nir_ ? 8 : 6);
    encode_rgb(c, *last, now);
    if (nir_) {
        encode_nir(c, (*last)[3], now[3]);
    }
    std::memcpy(last->data(), now.data(), nir_ ? 8 : 6);
}

void Rgb14Encoder::encode_rgb(Context& c, const std::array<std::uint16_t, 4>& last,
                              const std::array<std::uint16_t, 4>& now) {
    ArithmeticEncoder& enc = rgb_layer_.encoder;
    std::uint32_t sym = 0;
    for (unsigned k = 0; k < 3; ++k) {
        sym |= (low(last[k]) != low(now[k]) ? 1U : 0U) << (2 * k);
        sym |= (high(last[k]) != high(now[k]) ? 2U : 0U) << (2 * k);
    }
    const bool grey = low(now[0]) == low(now[1]) && low(now[0]) == low(now[2]) &&
                      high(now[0]) == high(now[1]) && high(now[0]) == high(now[2]);
    sym |= grey ? 0U : 1U << 6;
    enc.encode_symbol(c.byte_used, sym);
    std::int32_t diff_l = 0;
    std::int32_t diff_h = 0;
    if ((sym & 1U) != 0) {
        diff_l = low(now[0]) - low(last[0]);
        enc.encode_symbol(c.diff[0], static_cast<std::uint32_t>(diff_l) & 0xFFU);
    }
    if ((sym & 2U) != 0) {
        diff_h = high(now[0]) - high(last[0]);
        enc.encode_symbol(c.diff[1], static_cast<std::uint32_t>(diff_h) & 0xFFU);
    }
    if ((sym & (1U << 6)) != 0) {
        if ((sym & (1U << 2)) != 0) {
            enc.encode_symbol(c.diff[2], corrector(low(now[1]), diff_l + low(last[1])));
        }
        if ((sym & (1U << 4)) != 0) {
            diff_l = (diff_l + low(now[1]) - low(last[1])) / 2;
            enc.encode_symbol(c.diff[4], corrector(low(now[2]), diff_l + low(last[2])));
        }
        if ((sym & (1U << 3)) != 0) {
            enc.encode_symbol(c.diff[3], corrector(high(now[1]), diff_h + high(last[1])));
        }
        if ((sym & (1U << 5)) != 0) {
            diff_h = (diff_h + high(now[1]) - high(last[1])) / 2;
            enc.encode_symbol(c.diff[5], corrector(high(now[2]), diff_h + high(last[2])));
        }
    }
    rgb_layer_.changed |= sym != 0;
}

void Rgb14Encoder::encode_nir(Context& c, std::uint16_t last, std::uint16_t now) {
    ArithmeticEncoder& enc = nir_layer_.encoder;
    std::uint32_t sym = low(last) != low(now) ? 1U : 0U;
    sym |= high(last) != high(now) ? 2U : 0U;
    enc.encode_symbol(c.nir_used, sym);
    if ((sym & 1U) != 0) {
        enc.encode_symbol(c.nir_diff[0], fold_diff(static_cast<std::uint32_t>(low(now)),
                                                   static_cast<std::uint32_t>(low(last))));
    }
    if ((sym & 2U) != 0) {
        enc.encode_symbol(c.nir_diff[1], fold_diff(static_cast<std::uint32_t>(high(now)),
                                                   static_cast<std::uint32_t>(high(last))));
    }
    nir_layer_.changed |= sym != 0;
}

void Rgb14Encoder::finish(std::vector<std::span<const std::uint8_t>>& layers) {
    layers.push_back(rgb_layer_.finish());
    if (nir_) {
        layers.push_back(nir_layer_.finish());
    }
}

}  // namespace beamtrace::laz
