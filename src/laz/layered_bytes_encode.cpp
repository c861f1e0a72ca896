#include "laz/layered_bytes_encode.hpp"

namespace beamtrace::laz {

Byte14Encoder::Byte14Encoder(const std::uint8_t* first, std::size_t size, unsigned channel)
    : current_(channel) {
    layers_.reserve(size);
    for (std::size_t i = 0; i < size; ++i) {
        layers_.push_back(std::make_unique<EncodeLayer>());
    }
    start_context(channel, std::vector<std::uint8_t>(first, first + size));
}

Byte14Encoder::~Byte14Encoder() = default;

void Byte14Encoder::start_context(unsigned channel, const std::vector<std::uint8_t>& from) {
    auto c = std::make_unique<Context>();
    c->last = from;
    c->models.reserve(from.size());
    for (std::size_t i = 0; i < from.size(); ++i) {
        c->models.emplace_back(256, true);
        c->models.back().init();
    }
    contexts_[channel] = std::move(c);
}

void Byte14Encoder::encode(const std::uint8_t* item, unsigned channel) {
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
    for (std::size_t i = 0; i < layers_.size(); ++i) {
        EncodeLayer& layer = *layers_[i];
        layer.encoder.encode_symbol(c.models[i], fold_diff(item[i], values[i]));
        if (item[i] != values[i]) {
            layer.changed = true;
            values[i] = item[i];
        }
    }
}

void Byte14Encoder::finish(std::vector<std::span<const std::uint8_t>>& layers) {
    for (const std::unique_ptr<EncodeLayer>& layer : layers_) {
        layers.push_back(layer->finish());
    }
}

}  // namespace beamtrace::laz
