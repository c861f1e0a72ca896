#include "laz/arithmetic_decoder.hpp"

#include "laz/laz_items.hpp"

namespace beamtrace::laz {

void ArithmeticDecoder::init() {
    length_ = kMaxLength;
    value_ = 0;
    for (int i = 0; i < 4; ++i) {
        value_ = (value_ << 8) | next_byte();
    }
}

std::uint32_t ArithmeticDecoder::past_end_byte() {
    ++position_;
    if (position_ - bytes_.size() > kOverrunSlack) {
        throw CorruptData("compressed data truncated (the arithmetic decoder ran " +
                          std::to_string(position_ - bytes_.size()) + " bytes past the end of " +
                          std::to_string(bytes_.size()) + ")");
    }
    return 0;
}

void ArithmeticDecoder::throw_out_of_range() {
    throw CorruptData("corrupt compressed data (a raw value decoded out of its range)");
}

}  // namespace beamtrace::laz
