#include "laz/layered_point14.hpp"

#include "laz/item_bytes.hpp"
#include "laz/layered_point14_shared.hpp"

#include <bit>
#include <cstdlib>
#include <cstring>

#include "laz/laz_items.hpp"

namespace beamtrace::laz {

using point14::kGpsCodeFull;
using point14::kGpsMulti;
using point14::kGpsMultiMinus;
using point14::kGpsSymbols;
using point14::kReturnMap6;
using point14::Median5;
using point14::return_level;

/// A point's fields (the GPS time apart: its bits live in the context's sequences).
struct Point14Decoder::Fields {
    std::int32_t x = 0, y = 0, z = 0;
    std::uint16_t intensity = 0;
    unsigned return_number = 0, number_of_returns = 0;
    unsigned class_flags = 0, scan_direction = 0, edge = 0;
    unsigned classification = 0, user_data = 0;
    std::int16_t scan_angle = 0;
    std::uint16_t point_source = 0;
    bool gps_time_change = false;
};

/// The last point of a scanner channel and the models that code its successor.
struct Point14Decoder::Context : Fields, point14::ChannelModels {
    Context() : ChannelModels(false) {}

    /// Starts from the point `from` (the chunk's first, or another channel's last point) of GPS
    /// time bits `gps_time`; the predictors start afresh.
    void start_from(const Fields& from, std::uint64_t gps_time) {
        static_cast<Fields&>(*this) = from;
        gps_time_change = false;
        last_intensity.fill(intensity);
        last_z.fill(z);
        gps = {gps_time, 0, 0, 0};
    }
};

Point14Decoder::Point14Decoder(const std::uint8_t* first,
                               std::span<const std::span<const std::uint8_t>> layers) {
    for (std::size_t i = 0; i < kLayers; ++i) {
        layers_[i].emplace(layers[i]);
    }
    Fields raw;  // the first record's fields, the seed of its channel's context
    raw.x = load<std::int32_t>(first);
    raw.y = load<std::int32_t>(first + 4);
    raw.z = load<std::int32_t>(first + 8);
    raw.intensity = load<std::uint16_t>(first + 12);
    raw.return_number = first[14] & 0x0FU;
    raw.number_of_returns = first[14] >> 4U;
    raw.class_flags = first[15] & 0x0FU;
    raw.scan_direction = (first[15] >> 6U) & 1U;
    raw.edge = first[15] >> 7U;
    raw.classification = first[16];
    raw.user_data = first[17];
    raw.scan_angle = load<std::int16_t>(first + 18);
    raw.point_source = load<std::uint16_t>(first + 20);
    current_ = (first[15] >> 4U) & 3U;
    start_context(current_, raw, load<std::uint64_t>(first + 22));
}

Point14Decoder::~Point14Decoder() = default;

void Point14Decoder::start_context(unsigned channel, const Fields& from, std::uint64_t gps_time) {
    auto c = std::make_unique<Context>();
    c->start_from(from, gps_time);
    contexts_[channel] = std::move(c);
}

unsigned Point14Decoder::decode(std::uint8_t* out) {
    ArithmeticDecoder& dec = layers_[kXy]->decoder;
    Context* c = contexts_[current_].get();
    unsigned lpr = c->return_number == 1 ? 1U : 0U;
    lpr += c->return_number >= c->number_of_returns ? 2U : 0U;
    lpr += c->gps_time_change ? 4U : 0U;
    const std::uint32_t changed = dec.decode_symbol(c->changed_values[lpr]);
    if ((changed & (1U << 6)) != 0) {
        const std::uint32_t diff = dec.decode_symbol(c->scanner_channel);
        const unsigned channel = (current_ + diff + 1) % 4;
        if (!contexts_[channel]) {
            start_context(channel, *c, c->gps[c->gps_last]);
        }
        current_ = channel;
        c = contexts_[channel].get();
    }
    decode_returns(*c, changed);
    const unsigned n = c->number_of_returns;
    const unsigned r = c->return_number;
    decode_xyz(*c, changed);
    unsigned cpr = r == 1 ? 2U : 0U;
    cpr += r >= n ? 1U : 0U;
    decode_attributes(*c, changed, cpr);

    store(out, c->x);
    store(out + 4, c->y);
    store(out + 8, c->z);
    store(out + 12, c->intensity);
    out[14] = static_cast<std::uint8_t>((r & 0x0FU) | (n << 4U));
    out[15] = static_cast<std::uint8_t>(c->class_flags | (current_ << 4U) |
                                        (c->scan_direction << 6U) | (c->edge << 7U));
    out[16] = static_cast<std::uint8_t>(c->classification);
    out[17] = static_cast<std::uint8_t>(c->user_data);
    store(out + 18, c->scan_angle);
    store(out + 20, c->point_source);
    store(out + 22, c->gps[c->gps_last]);
    return current_;
}

void Point14Decoder::decode_returns(Context& c, std::uint32_t changed) {
    ArithmeticDecoder& dec = layers_[kXy]->decoder;
    const bool gps_change = (changed & (1U << 4)) != 0;
    const unsigned last_r = c.return_number;
    if ((changed & (1U << 2)) != 0) {
        c.number_of_returns =
            dec.decode_symbol(c.lazy(c.number_of_returns_models[c.number_of_returns], 16));
    }
    switch (changed & 3U) {
        case 0:
            break;
        case 1:
            c.return_number = (last_r + 1) % 16;
            break;
        case 2:
            c.return_number = (last_r + 15) % 16;
            break;
        default:
            if (gps_change) {
                c.return_number = dec.decode_symbol(c.lazy(c.return_number_models[last_r], 16));
            } else {
                const std::uint32_t sym = dec.decode_symbol(c.return_number_gps_same);
                c.return_number = (last_r + sym + 2) % 16;
            }
            break;
    }
}

void Point14Decoder::decode_xyz(Context& c, std::uint32_t changed) {
    ArithmeticDecoder& dec = layers_[kXy]->decoder;
    const unsigned n = c.number_of_returns;
    const unsigned r = c.return_number;
    const unsigned gps_change = (changed >> 4U) & 1U;
    const unsigned m = kReturnMap6[n][r];
    const std::uint32_t single = n == 1 ? 1U : 0U;
    Median5& mx = c.x_median[(m << 1U) | gps_change];
    const std::int32_t diff_x = c.dx.decompress(dec, mx.get(), single);
    c.x = static_cast<std::int32_t>(static_cast<std::uint32_t>(c.x) +
                                    static_cast<std::uint32_t>(diff_x));
    mx.add(diff_x);
    const std::uint32_t kx = c.dx.k();
    Median5& my = c.y_median[(m << 1U) | gps_change];
    const std::int32_t diff_y =
        c.dy.decompress(dec, my.get(), single + (kx < 20 ? (kx & ~1U) : 20U));
    c.y = static_cast<std::int32_t>(static_cast<std::uint32_t>(c.y) +
                                    static_cast<std::uint32_t>(diff_y));
    my.add(diff_y);
    Layer& lz = *layers_[kZ];
    if (lz.coded) {
        const std::uint32_t kxy = (c.dx.k() + c.dy.k()) / 2;
        const unsigned l = return_level(n, r);
        c.z = c.dz.decompress(lz.decoder, c.last_z[l], single + (kxy < 18 ? (kxy & ~1U) : 18U));
        c.last_z[l] = c.z;
    }
}

void Point14Decoder::decode_attributes(Context& c, std::uint32_t changed, unsigned cpr) {
    const unsigned gps_change = (changed >> 4U) & 1U;
    if (Layer& l = *layers_[kClassification]; l.coded) {
        const unsigned ccc = ((c.classification & 0x1FU) << 1U) + (cpr == 3 ? 1U : 0U);
        c.classification = l.decoder.decode_symbol(c.lazy(c.classification_models[ccc], 256));
    }
    if (Layer& l = *layers_[kFlags]; l.coded) {
        const unsigned last = (c.edge << 5U) | (c.scan_direction << 4U) | c.class_flags;
        const std::uint32_t flags = l.decoder.decode_symbol(c.lazy(c.flags_models[last], 64));
        c.edge = (flags >> 5U) & 1U;
        c.scan_direction = (flags >> 4U) & 1U;
        c.class_flags = flags & 0x0FU;
    }
    if (Layer& l = *layers_[kIntensity]; l.coded) {
        std::uint16_t& last = c.last_intensity[(cpr << 1U) | gps_change];
        c.intensity = static_cast<std::uint16_t>(c.intensity_ic.decompress(l.decoder, last, cpr));
        last = c.intensity;
    }
    if (Layer& l = *layers_[kScanAngle]; l.coded && (changed & (1U << 3)) != 0) {
        c.scan_angle = static_cast<std::int16_t>(
            c.scan_angle_ic.decompress(l.decoder, c.scan_angle, gps_change));
    }
    if (Layer& l = *layers_[kUserData]; l.coded) {
        c.user_data = l.decoder.decode_symbol(c.lazy(c.user_data_models[c.user_data / 4], 256));
    }
    if (Layer& l = *layers_[kPointSource]; l.coded && (changed & (1U << 5)) != 0) {
        c.point_source =
            static_cast<std::uint16_t>(c.point_source_ic.decompress(l.decoder, c.point_source));
    }
    if (Layer& l = *layers_[kGpsTime]; l.coded && gps_change != 0) {
        decode_gps_time(c, l.decoder);
    }
    c.gps_time_change = gps_change != 0;
}

namespace {

/// `diff` times `multi`, wrapping like the format's 32-bit product.
[[nodiscard]] std::int32_t times(std::int32_t multi, std::int32_t diff) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(multi) *
                                     static_cast<std::uint32_t>(diff));
}

[[nodiscard]] std::uint64_t plus(std::uint64_t time_bits, std::int32_t diff) {
    return time_bits + static_cast<std::uint64_t>(static_cast<std::int64_t>(diff));
}

}  // namespace

void Point14Decoder::decode_full_gps_time(Context& c, ArithmeticDecoder& dec) {
    c.gps_next = (c.gps_next + 1) & 3U;
    const auto high = static_cast<std::int32_t>(c.gps[c.gps_last] >> 32U);
    const auto decoded = static_cast<std::uint32_t>(c.gps_ic.decompress(dec, high, 8));
    c.gps[c.gps_next] = (static_cast<std::uint64_t>(decoded) << 32U) | dec.read_int();
    c.gps_last = c.gps_next;
    c.gps_diff[c.gps_last] = 0;
    c.gps_extreme[c.gps_last] = 0;
}

void Point14Decoder::decode_gps_time(Context& c, ArithmeticDecoder& dec) {
    // A switch to another sequence is followed by that sequence's code: a loop, not recursion,
    // so hostile data cannot grow the stack.
    for (;;) {
        const unsigned s = c.gps_last;
        if (c.gps_diff[s] == 0) {
            const std::uint32_t multi = dec.decode_symbol(c.gps_0diff);
            if (multi == 0) {
                c.gps_diff[s] = c.gps_ic.decompress(dec, 0, 0);
                c.gps[s] = plus(c.gps[s], c.gps_diff[s]);
                c.gps_extreme[s] = 0;
            } else if (multi == 1) {
                decode_full_gps_time(c, dec);
            } else {
                c.gps_last = (s + multi - 1) & 3U;
                continue;
            }
            return;
        }
        const std::uint32_t multi = dec.decode_symbol(c.gps_multi);
        if (multi == 1) {
            c.gps[s] = plus(c.gps[s], c.gps_ic.decompress(dec, c.gps_diff[s], 1));
            c.gps_extreme[s] = 0;
        } else if (multi < kGpsCodeFull) {
            c.gps[s] =
                plus(c.gps[s], decode_gps_multiple(c, dec, static_cast<std::int32_t>(multi)));
        } else if (multi == kGpsCodeFull) {
            decode_full_gps_time(c, dec);
        } else {
            c.gps_last = (s + multi - kGpsCodeFull) & 3U;
            continue;
        }
        return;
    }
}

std::int32_t Point14Decoder::decode_gps_multiple(Context& c, ArithmeticDecoder& dec,
                                                 std::int32_t multi) {
    const unsigned s = c.gps_last;
    const std::int32_t last = c.gps_diff[s];
    std::int32_t diff = 0;
    bool extreme = false;
    if (multi == 0) {
        diff = c.gps_ic.decompress(dec, 0, 7);
        extreme = true;
    } else if (multi < kGpsMulti) {
        diff = c.gps_ic.decompress(dec, times(multi, last), multi < 10 ? 2 : 3);
    } else if (multi == kGpsMulti) {
        diff = c.gps_ic.decompress(dec, times(kGpsMulti, last), 4);
        extreme = true;
    } else {
        const std::int32_t negative = kGpsMulti - multi;
        if (negative > kGpsMultiMinus) {
            diff = c.gps_ic.decompress(dec, times(negative, last), 5);
        } else {
            diff = c.gps_ic.decompress(dec, times(kGpsMultiMinus, last), 6);
            extreme = true;
        }
    }
    if (extreme && ++c.gps_extreme[s] > 3) {
        c.gps_diff[s] = diff;
        c.gps_extreme[s] = 0;
    }
    return diff;
}

}  // namespace beamtrace::laz
