// The decoder of LASzip's range coder over one chunk's (or one layer's) bytes.
//
// It never reads outside its span: past the end it reads zero bytes (a well-formed stream ends
// with the encoder's padding, so a few are harmless) and throws laz::CorruptData once it has
// read more than kOverrunSlack of them, or when a raw value decodes out of its range. The hot
// operations are inline: no virtual call, no allocation per symbol.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "laz/arithmetic_model.hpp"

namespace beamtrace::laz {

class ArithmeticDecoder {
  public:
    /// Zero bytes past the end tolerated before the stream counts as truncated.
    static constexpr std::size_t kOverrunSlack = 8;

    explicit ArithmeticDecoder(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

    /// Reads the first four bytes and starts decoding.
    void init();

    std::uint32_t decode_bit(ArithmeticBitModel& m) {
        const std::uint32_t x = m.bit0_prob_ * (length_ >> kBitLengthShift);
        const std::uint32_t sym = value_ >= x ? 1U : 0U;
        if (sym == 0) {
            length_ = x;
            ++m.bit0_count_;
        } else {
            value_ -= x;
            length_ -= x;
        }
        if (length_ < kMinLength) {
            renormalise();
        }
        if (--m.until_update_ == 0) {
            m.update();
        }
        return sym;
    }

    std::uint32_t decode_symbol(ArithmeticModel& m) {
        const std::uint32_t sym = m.table_size_ != 0 ? find_with_table(m) : find_by_bisection(m);
        if (length_ < kMinLength) {
            renormalise();
        }
        ++m.counts()[sym];
        if (--m.until_update_ == 0) {
            m.update();
        }
        return sym;
    }

    /// A raw value of `bits` bits (1 to 32).
    std::uint32_t read_bits(unsigned bits) {
        if (bits > 19) {
            const std::uint32_t low = read_short();
            return (read_bits(bits - 16) << 16) | low;
        }
        length_ >>= bits;
        const std::uint32_t sym = value_ / length_;
        value_ -= length_ * sym;
        if (length_ < kMinLength) {
            renormalise();
        }
        if (sym >= (1U << bits)) {
            throw_out_of_range();
        }
        return sym;
    }

    std::uint32_t read_bit() { return read_bits(1); }
    std::uint32_t read_byte() { return read_bits(8); }
    std::uint32_t read_short() { return read_bits(16); }
    /// 32 bits: the low 16 first.
    std::uint32_t read_int() {
        const std::uint32_t low = read_short();
        return (read_short() << 16) | low;
    }
    /// 64 bits: the low 32 first.
    std::uint64_t read_int64() {
        const std::uint64_t low = read_int();
        return (static_cast<std::uint64_t>(read_int()) << 32) | low;
    }

    /// Bytes consumed so far (past-the-end zeros included).
    [[nodiscard]] std::size_t position() const { return position_; }

  private:
    std::uint32_t next_byte() {
        if (position_ < bytes_.size()) {
            return bytes_[position_++];
        }
        return past_end_byte();
    }
    std::uint32_t past_end_byte();
    [[noreturn]] static void throw_out_of_range();

    void renormalise() {
        do {
            value_ = (value_ << 8) | next_byte();
            length_ <<= 8;
        } while (length_ < kMinLength);
    }

    std::uint32_t find_with_table(ArithmeticModel& m);
    std::uint32_t find_by_bisection(ArithmeticModel& m);

    std::span<const std::uint8_t> bytes_;
    std::size_t position_ = 0;
    std::uint32_t value_ = 0;
    std::uint32_t length_ = kMaxLength;
};

inline std::uint32_t ArithmeticDecoder::find_with_table(ArithmeticModel& m) {
    const std::uint32_t* dist = m.distribution();
    const std::uint32_t* lookup = m.table();
    const std::uint32_t old_length = length_;
    length_ >>= kSymbolLengthShift;
    const std::uint32_t dv = value_ / length_;
    std::uint32_t t = dv >> m.table_shift_;
    if (t > m.table_size_) {  // only reachable from corrupt bytes; keeps t + 1 in the table
        t = m.table_size_;
    }
    std::uint32_t sym = lookup[t];
    std::uint32_t n = lookup[t + 1] + 1;
    while (n > sym + 1) {
        const std::uint32_t k = (sym + n) >> 1;
        if (dist[k] > dv) {
            n = k;
        } else {
            sym = k;
        }
    }
    const std::uint32_t x = dist[sym] * length_;
    const std::uint32_t y = sym != m.last_symbol_ ? dist[sym + 1] * length_ : old_length;
    value_ -= x;
    length_ = y - x;
    return sym;
}

inline std::uint32_t ArithmeticDecoder::find_by_bisection(ArithmeticModel& m) {
    const std::uint32_t* dist = m.distribution();
    std::uint32_t x = 0;
    std::uint32_t y = length_;
    std::uint32_t sym = 0;
    std::uint32_t n = m.symbols_;
    length_ >>= kSymbolLengthShift;
    std::uint32_t k = n >> 1;
    do {
        const std::uint32_t z = length_ * dist[k];
        if (z > value_) {
            n = k;
            y = z;
        } else {
            sym = k;
            x = z;
        }
        k = (sym + n) >> 1;
    } while (k != sym);
    value_ -= x;
    length_ = y - x;
    return sym;
}

}  // namespace beamtrace::laz
