#include "laz/layered_bytes.hpp"

#include <cstring>

namespace beamtrace::laz {

Byte14Decoder::Byte14Decoder(const std::uint8_t* first,
                             std::span<const std::span<const std::uint8_t>> layers,
                             unsigned channel) {
    layers_.reserve(layers.size());
    for (std::size_t i = 0; i < layers.size(); ++i) {
        layers_.emplace_back(layers[i]);
        if (layers_.back().coded) {
            coded_.push_back(i);
        }
    }
    current_ = channel;
    start_context(channel, std::vector<std::uint8_t>(first, first + layers.size()));
}

Byte14Decoder::~Byte14Decoder() = default;

void Byte14Decoder::start_context(unsigned channel, const std::vector<std::uint8_t>& from) {
    auto c = std::make_unique<Context>();
    c->last = from;
    c->models.resize(from.size());
    for (const std::size_t i : coded_) {
        c->models[i].emplace(256, false);
        c->models[i]->init();
    }
    contexts_[channel] = std::move(c);
}

void Byte14Decoder::decode(std::uint8_t* out, unsigned channel) {
    std::vector<std::uint8_t>* last = &contexts_[current_]->last;
    if (channel != current_) {
        current_ = channel;
        if (!contexts_[channel]) {
            start_context(channel, *last);
            last = &contexts_[channel]->last;
        }
    }
    Context& c = *contexts_[current_];
    std::uint8_t* values = last->data();
    for (const std::size_t i : coded_) {
        values[i] = fold_byte(layers_[i].decoder.decode_symbol(*c.models[i]), values[i]);
    }
    std::memcpy(out, values, last->size());
}

}  // namespace beamtrace::laz
