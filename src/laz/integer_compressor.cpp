#include "laz/integer_compressor.hpp"

#include <bit>

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace beamtrace::laz {

IntegerCompressor::IntegerCompressor(std::uint32_t bits, std::uint32_t contexts,
                                     std::uint32_t bits_high, std::uint32_t range)
    : bits_(bits), contexts_(contexts), bits_high_(bits_high) {
    if (contexts == 0 || bits_high == 0 || bits_high > 11 || bits > 32) {
        throw std::invalid_argument(
            "integer compressor: bits 0..32, contexts >= 1, bits_high 1..11");
    }
    if (range != 0) {
        corr_range_ = range;
        while (range != 0) {
            range >>= 1;
            ++corr_bits_;
        }
        if (corr_range_ == (1U << (corr_bits_ - 1))) {
            --corr_bits_;
        }
        corr_min_ = -static_cast<std::int32_t>(corr_range_ / 2);
        corr_max_ =
            static_cast<std::int32_t>(static_cast<std::uint32_t>(corr_min_) + corr_range_ - 1);
    } else if (bits != 0 && bits < 32) {
        corr_bits_ = bits;
        corr_range_ = 1U << bits;
        corr_min_ = -static_cast<std::int32_t>(corr_range_ / 2);
        corr_max_ = corr_min_ + static_cast<std::int32_t>(corr_range_) - 1;
    } else {
        corr_bits_ = 32;
        corr_range_ = 0;
        corr_min_ = std::numeric_limits<std::int32_t>::min();
        corr_max_ = std::numeric_limits<std::int32_t>::max();
    }
}

void IntegerCompressor::init_models(bool compress) {
    if (k_models_.empty() || models_compress_ != compress) {
        models_compress_ = compress;
        k_models_.clear();
        corrector_models_.clear();
        k_models_.reserve(contexts_);
        for (std::uint32_t i = 0; i < contexts_; ++i) {
            k_models_.emplace_back(corr_bits_ + 1, compress);
        }
        corrector_models_.reserve(corr_bits_);
        for (std::uint32_t k = 1; k <= corr_bits_; ++k) {
            corrector_models_.emplace_back(1U << std::min(k, bits_high_), compress);
        }
    }
    for (ArithmeticModel& m : k_models_) {
        m.init();
    }
    corrector0_.init();
    for (ArithmeticModel& m : corrector_models_) {
        m.init();
    }
}

std::int32_t IntegerCompressor::decompress(ArithmeticDecoder& dec, std::int32_t pred,
                                           std::uint32_t context) {
    assert(context < contexts_ && !k_models_.empty() && !models_compress_);
    // Wrapping arithmetic: the format folds the sum back into [0, corr_range).
    std::uint32_t real = static_cast<std::uint32_t>(pred) +
                         static_cast<std::uint32_t>(read_corrector(dec, k_models_[context]));
    if (static_cast<std::int32_t>(real) < 0) {
        real += corr_range_;
    } else if (real >= corr_range_) {
        real -= corr_range_;
    }
    return static_cast<std::int32_t>(real);
}

void IntegerCompressor::compress(ArithmeticEncoder& enc, std::int32_t pred, std::int32_t real,
                                 std::uint32_t context) {
    assert(context < contexts_ && !k_models_.empty() && models_compress_);
    std::int32_t corr = static_cast<std::int32_t>(static_cast<std::uint32_t>(real) -
                                                  static_cast<std::uint32_t>(pred));
    if (corr < corr_min_) {
        corr = static_cast<std::int32_t>(static_cast<std::uint32_t>(corr) + corr_range_);
    } else if (corr > corr_max_) {
        corr = static_cast<std::int32_t>(static_cast<std::uint32_t>(corr) - corr_range_);
    }
    write_corrector(enc, corr, k_models_[context]);
}

std::int32_t IntegerCompressor::read_corrector(ArithmeticDecoder& dec, ArithmeticModel& k_model) {
    k_ = dec.decode_symbol(k_model);
    if (k_ == 0) {
        return static_cast<std::int32_t>(dec.decode_bit(corrector0_));
    }
    if (k_ >= 32) {
        return corr_min_;
    }
    std::uint32_t c = dec.decode_symbol(corrector_models_[k_ - 1]);
    if (k_ > bits_high_) {
        const std::uint32_t low_bits = k_ - bits_high_;
        c = (c << low_bits) | dec.read_bits(low_bits);
    }
    // [2^(k-1), 2^k - 1] maps back to [2^(k-1) + 1, 2^k]; [0, 2^(k-1) - 1] to [-(2^k - 1),
    // -2^(k-1)].
    if (c >= (1U << (k_ - 1))) {
        return static_cast<std::int32_t>(c + 1);
    }
    return static_cast<std::int32_t>(c - ((1U << k_) - 1));
}

void IntegerCompressor::write_corrector(ArithmeticEncoder& enc, std::int32_t c,
                                        ArithmeticModel& k_model) {
    // The smallest k with c in [-(2^k - 1), 2^k].
    const std::uint32_t c1 =
        c <= 0 ? 0U - static_cast<std::uint32_t>(c) : static_cast<std::uint32_t>(c) - 1;
    k_ = static_cast<std::uint32_t>(std::bit_width(c1));
    enc.encode_symbol(k_model, k_);
    if (k_ == 0) {
        enc.encode_bit(corrector0_, static_cast<std::uint32_t>(c));
        return;
    }
    if (k_ >= 32) {
        return;
    }
    std::uint32_t u = static_cast<std::uint32_t>(c);
    u = c < 0 ? u + ((1U << k_) - 1) : u - 1;
    if (k_ <= bits_high_) {
        enc.encode_symbol(corrector_models_[k_ - 1], u);
        return;
    }
    const std::uint32_t low_bits = k_ - bits_high_;
    enc.encode_symbol(corrector_models_[k_ - 1], u >> low_bits);
    enc.write_bits(low_bits, u & ((1U << low_bits) - 1));
}

}  // namespace beamtrace::laz
