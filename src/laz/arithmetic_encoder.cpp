#include "laz/arithmetic_encoder.hpp"

#include <cassert>

namespace beamtrace::laz {

void ArithmeticEncoder::init() {
    start_ = out_->size();
    base_ = 0;
    length_ = kMaxLength;
}

void ArithmeticEncoder::done() {
    const std::uint32_t before = base_;
    bool another_byte = true;
    if (length_ > 2 * kMinLength) {
        base_ += kMinLength;
        length_ = kMinLength >> 1;
    } else {
        base_ += kMinLength >> 1;
        length_ = kMinLength >> 9;
        another_byte = false;
    }
    if (before > base_) {
        propagate_carry();
    }
    renormalise();
    out_->push_back(0);
    out_->push_back(0);
    if (another_byte) {
        out_->push_back(0);
    }
}

void ArithmeticEncoder::propagate_carry() {
    // The interval's base never exceeds 1.0, so the carry stops inside this stream.
    std::size_t p = out_->size();
    while (p > start_) {
        --p;
        std::uint8_t& byte = (*out_)[p];
        if (byte != 0xFFU) {
            ++byte;
            return;
        }
        byte = 0;
    }
    assert(false && "carry out of the stream");
}

}  // namespace beamtrace::laz
