// The encoder of LASzip's range coder, appending to a byte vector. done() writes the final
// bytes and the zero padding that keeps a decoder's reads inside the stream.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "laz/arithmetic_model.hpp"

namespace beamtrace::laz {

class ArithmeticEncoder {
  public:
    /// Appends to `out` (which must outlive the encoder); init() starts a stream at its end.
    explicit ArithmeticEncoder(std::vector<std::uint8_t>& out) : out_(&out) { init(); }

    /// Starts a new stream at the current end of the output.
    void init();
    /// Ends the stream: its last bytes and two or three zeros.
    void done();

    void encode_bit(ArithmeticBitModel& m, std::uint32_t sym) {
        const std::uint32_t x = m.bit0_prob_ * (length_ >> kBitLengthShift);
        if (sym == 0) {
            length_ = x;
            ++m.bit0_count_;
        } else {
            add_to_base(x);
            length_ -= x;
        }
        if (length_ < kMinLength) {
            renormalise();
        }
        if (--m.until_update_ == 0) {
            m.update();
        }
    }

    void encode_symbol(ArithmeticModel& m, std::uint32_t sym) {
        const std::uint32_t* dist = m.distribution();
        if (sym == m.last_symbol_) {
            const std::uint32_t x = dist[sym] * (length_ >> kSymbolLengthShift);
            add_to_base(x);
            length_ -= x;
        } else {
            length_ >>= kSymbolLengthShift;
            const std::uint32_t x = dist[sym] * length_;
            add_to_base(x);
            length_ = dist[sym + 1] * length_ - x;
        }
        if (length_ < kMinLength) {
            renormalise();
        }
        ++m.counts()[sym];
        if (--m.until_update_ == 0) {
            m.update();
        }
    }

    /// `sym` raw in `bits` bits (1 to 32; sym < 2^bits).
    void write_bits(unsigned bits, std::uint32_t sym) {
        if (bits > 19) {
            write_short(sym & 0xFFFFU);
            sym >>= 16;
            bits -= 16;
        }
        length_ >>= bits;
        add_to_base(sym * length_);
        if (length_ < kMinLength) {
            renormalise();
        }
    }

    void write_bit(std::uint32_t sym) { write_bits(1, sym); }
    void write_byte(std::uint32_t sym) { write_bits(8, sym); }
    void write_short(std::uint32_t sym) { write_bits(16, sym); }
    void write_int(std::uint32_t sym) {
        write_short(sym & 0xFFFFU);
        write_short(sym >> 16);
    }
    void write_int64(std::uint64_t sym) {
        write_int(static_cast<std::uint32_t>(sym));
        write_int(static_cast<std::uint32_t>(sym >> 32));
    }

  private:
    void add_to_base(std::uint32_t x) {
        const std::uint32_t before = base_;
        base_ += x;
        if (before > base_) {
            propagate_carry();
        }
    }
    void propagate_carry();
    void renormalise() {
        do {
            out_->push_back(static_cast<std::uint8_t>(base_ >> 24));
            base_ <<= 8;
            length_ <<= 8;
        } while (length_ < kMinLength);
    }

    std::vector<std::uint8_t>* out_;
    std::size_t start_ = 0;  ///< where this stream began in *out_
    std::uint32_t base_ = 0;
    std::uint32_t length_ = kMaxLength;
};

}  // namespace beamtrace::laz
