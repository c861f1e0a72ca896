// BYTE version 2 (the extra bytes of a record): each byte's difference to the previous
// record's, with one model per byte position.
#include "laz/items_v2.hpp"

namespace beamtrace::laz {

ByteCodecV2::ByteCodecV2(std::size_t count, bool compress) : last_(count, 0) {
    models_.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        models_.emplace_back(256, compress);
    }
}

void ByteCodecV2::init(const std::uint8_t* item) {
    for (ArithmeticModel& m : models_) {
        m.init();
    }
    std::copy(item, item + last_.size(), last_.begin());
}

void ByteCodecV2::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    for (std::size_t i = 0; i < last_.size(); ++i) {
        last_[i] = static_cast<std::uint8_t>(last_[i] + dec.decode_symbol(models_[i]));
        item[i] = last_[i];
    }
}

void ByteCodecV2::encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
    for (std::size_t i = 0; i < last_.size(); ++i) {
        enc.encode_symbol(models_[i], static_cast<std::uint8_t>(item[i] - last_[i]));
        last_[i] = item[i];
    }
}

}  // namespace beamtrace::laz
