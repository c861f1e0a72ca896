// GPSTIME11 version 2. The time's 64 bits are coded as an integer: up to four sequences (the
// interleaved pulses of several scanners or mirrors) each keep their last time and last
// difference; a symbol says how the new difference relates to the last one (a multiplier, a
// new sequence, a switch to another sequence, or no change).
#include <algorithm>

#include "laz/items_v2.hpp"
#include "laz/laz_items.hpp"

namespace beamtrace::laz {
namespace {

constexpr std::uint32_t kMulti = 500;          ///< largest multiplier coded directly
constexpr std::int32_t kMultiMinus = -10;      ///< smallest negative multiplier
constexpr std::uint32_t kUnchanged = 511;      ///< kMulti - kMultiMinus + 1
constexpr std::uint32_t kCodeFull = 512;       ///< a new sequence (full time follows)
constexpr std::uint32_t kMultiSymbols = 516;   ///< kCodeFull + 3 switches + 1
constexpr std::uint32_t kZeroDiffSymbols = 6;  ///< unchanged, 32-bit, new, 3 switches
constexpr int kMaxSwitches = 4;                ///< a valid stream switches at most once

/// Whether a 64-bit difference fits in 32 bits (then it is `out`).
bool fits_i32(std::uint64_t a, std::uint64_t b, std::int32_t& out) {
    const auto d = static_cast<std::int64_t>(a - b);
    out = static_cast<std::int32_t>(d);
    return d == static_cast<std::int64_t>(out);
}

std::uint64_t add_i32(std::uint64_t t, std::int32_t d) {
    return t + static_cast<std::uint64_t>(static_cast<std::int64_t>(d));
}

/// The multiplier between two differences, rounded as the format does (in float).
std::int32_t multiplier(std::int32_t diff, std::int32_t last_diff) {
    float f = static_cast<float>(diff) / static_cast<float>(last_diff);
    f = std::clamp(f, -1.0e6F, 1.0e6F);  // beyond kMulti all are alike; keeps the cast defined
    return f >= 0 ? static_cast<std::int32_t>(f + 0.5F) : static_cast<std::int32_t>(f - 0.5F);
}

}  // namespace

Gpstime11CodecV2::Gpstime11CodecV2(bool compress)
    : multi_(kMultiSymbols, compress),
      zero_diff_(kZeroDiffSymbols, compress),
      ic_(32, 9),
      compress_(compress) {}

void Gpstime11CodecV2::init(const std::uint8_t* item) {
    multi_.init();
    zero_diff_.init();
    if (compress_) {
        ic_.init_compressor();
    } else {
        ic_.init_decompressor();
    }
    last_ = 0;
    next_ = 0;
    time_ = {load_u64(item), 0, 0, 0};
    diff_.fill(0);
    extreme_.fill(0);
}

void Gpstime11CodecV2::count_extreme(std::int32_t diff) {
    if (++extreme_[last_] > 3) {
        diff_[last_] = diff;
        extreme_[last_] = 0;
    }
}

void Gpstime11CodecV2::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    for (int i = 0; i < kMaxSwitches; ++i) {
        if (decode_step(dec)) {
            store_u64(item, time_[last_]);
            return;
        }
    }
    throw CorruptData("GPSTIME11: endless switching between time sequences");
}

bool Gpstime11CodecV2::decode_step(ArithmeticDecoder& dec) {
    if (diff_[last_] == 0) {
        const std::uint32_t multi = dec.decode_symbol(zero_diff_);
        if (multi == 1) {
            diff_[last_] = ic_.decompress(dec, 0, 0);
            time_[last_] = add_i32(time_[last_], diff_[last_]);
            extreme_[last_] = 0;
        } else if (multi == 2) {
            decode_new_sequence(dec);
        } else if (multi > 2) {
            last_ = (last_ + multi - 2) & 3U;
            return false;
        }
        return true;
    }
    const std::uint32_t multi = dec.decode_symbol(multi_);
    if (multi == 1) {
        time_[last_] = add_i32(time_[last_], ic_.decompress(dec, diff_[last_], 1));
        extreme_[last_] = 0;
    } else if (multi < kUnchanged) {
        decode_multiplied(dec, multi);
    } else if (multi == kCodeFull) {
        decode_new_sequence(dec);
    } else if (multi > kCodeFull) {
        last_ = (last_ + multi - kCodeFull) & 3U;
        return false;
    }
    return true;
}

void Gpstime11CodecV2::decode_multiplied(ArithmeticDecoder& dec, std::uint32_t multi) {
    const std::int32_t last = diff_[last_];
    std::int32_t d = 0;
    if (multi == 0) {
        d = ic_.decompress(dec, 0, 7);
        count_extreme(d);
    } else if (multi < kMulti) {
        d = ic_.decompress(dec, wrap_mul(static_cast<std::int32_t>(multi), last),
                           multi < 10 ? 2 : 3);
    } else if (multi == kMulti) {
        d = ic_.decompress(dec, wrap_mul(static_cast<std::int32_t>(kMulti), last), 4);
        count_extreme(d);
    } else {
        const std::int32_t negative =
            static_cast<std::int32_t>(kMulti) - static_cast<std::int32_t>(multi);
        if (negative > kMultiMinus) {
            d = ic_.decompress(dec, wrap_mul(negative, last), 5);
        } else {
            d = ic_.decompress(dec, wrap_mul(kMultiMinus, last), 6);
            count_extreme(d);
        }
    }
    time_[last_] = add_i32(time_[last_], d);
}

void Gpstime11CodecV2::decode_new_sequence(ArithmeticDecoder& dec) {
    next_ = (next_ + 1) & 3U;
    const auto high = static_cast<std::uint32_t>(
        ic_.decompress(dec, static_cast<std::int32_t>(time_[last_] >> 32), 8));
    time_[next_] = (static_cast<std::uint64_t>(high) << 32) | dec.read_int();
    last_ = next_;
    diff_[last_] = 0;
    extreme_[last_] = 0;
}

void Gpstime11CodecV2::encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
    const std::uint64_t time = load_u64(item);
    // A switch is followed by a step in the new sequence, which never switches again.
    while (!encode_step(enc, time)) {
    }
}

bool Gpstime11CodecV2::encode_step(ArithmeticEncoder& enc, std::uint64_t time) {
    const bool zero_diff = diff_[last_] == 0;
    ArithmeticModel& model = zero_diff ? zero_diff_ : multi_;
    if (time == time_[last_]) {
        enc.encode_symbol(model, zero_diff ? 0 : kUnchanged);
        return true;
    }
    std::int32_t d = 0;
    if (fits_i32(time, time_[last_], d)) {
        if (zero_diff) {
            enc.encode_symbol(zero_diff_, 1);
            ic_.compress(enc, 0, d, 0);
            diff_[last_] = d;
            extreme_[last_] = 0;
        } else {
            encode_multiplied(enc, d);
        }
    } else {
        const std::uint32_t full = zero_diff ? 2 : kCodeFull;
        if (switch_sequence(enc, model, full, time)) {
            return false;
        }
        encode_new_sequence(enc, model, full, time);
    }
    time_[last_] = time;
    return true;
}

void Gpstime11CodecV2::encode_multiplied(ArithmeticEncoder& enc, std::int32_t d) {
    const std::int32_t last = diff_[last_];
    const std::int32_t multi = multiplier(d, last);
    if (multi == 1) {
        enc.encode_symbol(multi_, 1);
        ic_.compress(enc, last, d, 1);
        extreme_[last_] = 0;
    } else if (multi > 0 && multi < static_cast<std::int32_t>(kMulti)) {
        enc.encode_symbol(multi_, static_cast<std::uint32_t>(multi));
        ic_.compress(enc, wrap_mul(multi, last), d, multi < 10 ? 2 : 3);
    } else if (multi > 0) {
        enc.encode_symbol(multi_, kMulti);
        ic_.compress(enc, wrap_mul(static_cast<std::int32_t>(kMulti), last), d, 4);
        count_extreme(d);
    } else if (multi < 0 && multi > kMultiMinus) {
        enc.encode_symbol(multi_,
                          static_cast<std::uint32_t>(static_cast<std::int32_t>(kMulti) - multi));
        ic_.compress(enc, wrap_mul(multi, last), d, 5);
    } else if (multi < 0) {
        enc.encode_symbol(multi_, kMulti - static_cast<std::uint32_t>(kMultiMinus));
        ic_.compress(enc, wrap_mul(kMultiMinus, last), d, 6);
        count_extreme(d);
    } else {
        enc.encode_symbol(multi_, 0);
        ic_.compress(enc, 0, d, 7);
        count_extreme(d);
    }
}

bool Gpstime11CodecV2::switch_sequence(ArithmeticEncoder& enc, ArithmeticModel& m,
                                       std::uint32_t base, std::uint64_t time) {
    for (std::uint32_t i = 1; i < 4; ++i) {
        std::int32_t d = 0;
        if (fits_i32(time, time_[(last_ + i) & 3U], d)) {
            enc.encode_symbol(m, base + i);
            last_ = (last_ + i) & 3U;
            return true;
        }
    }
    return false;
}

void Gpstime11CodecV2::encode_new_sequence(ArithmeticEncoder& enc, ArithmeticModel& m,
                                           std::uint32_t symbol, std::uint64_t time) {
    enc.encode_symbol(m, symbol);
    ic_.compress(enc, static_cast<std::int32_t>(time_[last_] >> 32),
                 static_cast<std::int32_t>(time >> 32), 8);
    enc.write_int(static_cast<std::uint32_t>(time));
    next_ = (next_ + 1) & 3U;
    last_ = next_;
    diff_[last_] = 0;
    extreme_[last_] = 0;
}

}  // namespace beamtrace::laz
