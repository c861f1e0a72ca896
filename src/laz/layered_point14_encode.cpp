#include "laz/layered_point14_encode.hpp"

#include <bit>

#include "laz/arithmetic_model.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/item_bytes.hpp"
#include "laz/layered_point14_shared.hpp"

namespace beamtrace::laz {

using point14::kGpsCodeFull;
using point14::kGpsMulti;
using point14::kGpsMultiMinus;
using point14::kGpsSymbols;
using point14::Median5;

/// A record's fields, as the format compares and codes them.
struct Point14Encoder::Fields {
    std::int32_t x = 0, y = 0, z = 0;
    std::uint16_t intensity = 0;
    unsigned return_number = 0, number_of_returns = 0;
    unsigned class_flags = 0, channel = 0, scan_direction = 0, edge = 0;
    unsigned classification = 0, user_data = 0;
    std::int16_t scan_angle = 0;
    std::uint16_t point_source = 0;
    std::uint64_t gps_time = 0;  ///< the double's bits
    bool gps_time_change = false;

    static Fields unpack(const std::uint8_t* r) {
        Fields f;
        f.x = load<std::int32_t>(r);
        f.y = load<std::int32_t>(r + 4);
        f.z = load<std::int32_t>(r + 8);
        f.intensity = load<std::uint16_t>(r + 12);
        f.return_number = r[14] & 0x0FU;
        f.number_of_returns = r[14] >> 4U;
        f.class_flags = r[15] & 0x0FU;
        f.channel = (r[15] >> 4U) & 3U;
        f.scan_direction = (r[15] >> 6U) & 1U;
        f.edge = r[15] >> 7U;
        f.classification = r[16];
        f.user_data = r[17];
        f.scan_angle = load<std::int16_t>(r + 18);
        f.point_source = load<std::uint16_t>(r + 20);
        f.gps_time = load<std::uint64_t>(r + 22);
        return f;
    }
    [[nodiscard]] unsigned flags() const {
        return (edge << 5U) | (scan_direction << 4U) | class_flags;
    }
};

namespace {

/// LASzip compares GPS times as doubles (so 0.0 and -0.0 are the same time, NaN never is).
[[nodiscard]] bool same_time(std::uint64_t a, std::uint64_t b) {
    return std::bit_cast<double>(a) == std::bit_cast<double>(b);
}

/// LASzip's I32_QUANTIZE of a float, with x86's result (INT32_MIN) where the float is out of
/// the int32 range.
[[nodiscard]] std::int32_t quantize(float f) {
    const float r = f >= 0.0F ? f + 0.5F : f - 0.5F;
    if (!(r >= -2147483648.0F && r < 2147483648.0F)) {
        return INT32_MIN;
    }
    return static_cast<std::int32_t>(r);
}

}  // namespace

/// The last point of a scanner channel and the models that code its successor.
struct Point14Encoder::Context : point14::ChannelModels {
    Fields last;

    explicit Context(const Fields& from) : ChannelModels(true), last(from) {
        last.gps_time_change = false;
        last_intensity.fill(from.intensity);
        last_z.fill(from.z);
        gps = {from.gps_time, 0, 0, 0};
    }
};

Point14Encoder::Point14Encoder(const std::uint8_t* first) {
    const Fields raw = Fields::unpack(first);
    current_ = raw.channel;
    start_context(current_, raw);
}

Point14Encoder::~Point14Encoder() = default;

void Point14Encoder::start_context(unsigned channel, const Fields& from) {
    contexts_[channel] = std::make_unique<Context>(from);
}

namespace {

/// The 7-bit mask of what changed from `last` (the last point of the record's channel) to `p`.
[[nodiscard]] std::uint32_t changed_mask(const Point14Encoder::Fields& last,
                                         const Point14Encoder::Fields& p, bool switched) {
    std::uint32_t changed = (switched ? 1U << 6 : 0U) |
                            (p.point_source != last.point_source ? 1U << 5 : 0U) |
                            (!same_time(p.gps_time, last.gps_time) ? 1U << 4 : 0U) |
                            (p.scan_angle != last.scan_angle ? 1U << 3 : 0U) |
                            (p.number_of_returns != last.number_of_returns ? 1U << 2 : 0U);
    const unsigned r = p.return_number;
    const unsigned last_r = last.return_number;
    if (r != last_r) {
        changed |= r == (last_r + 1) % 16 ? 1U : r == (last_r + 15) % 16 ? 2U : 3U;
    }
    return changed;
}

}  // namespace

unsigned Point14Encoder::encode(const std::uint8_t* record) {
    ArithmeticEncoder& enc = layers_[kXy].encoder;
    const Fields p = Fields::unpack(record);
    Context* c = contexts_[current_].get();
    unsigned lpr = c->last.return_number == 1 ? 1U : 0U;
    lpr += c->last.return_number >= c->last.number_of_returns ? 2U : 0U;
    lpr += c->last.gps_time_change ? 4U : 0U;
    const bool switched = p.channel != current_;
    // A switch to a channel seen before compares with that channel's last point; a switch to
    // a new one with the current channel's (which the new context starts from).
    const Fields& last = switched && contexts_[p.channel] ? contexts_[p.channel]->last : c->last;
    const std::uint32_t changed = changed_mask(last, p, switched);
    enc.encode_symbol(c->changed_values[lpr], changed);
    if (switched) {
        enc.encode_symbol(c->scanner_channel, (p.channel + 4 - current_ - 1) % 4);
        if (!contexts_[p.channel]) {
            start_context(p.channel, c->last);
        }
        current_ = p.channel;
        c = contexts_[current_].get();
    }
    encode_returns(*c, p, changed);
    encode_xyz(*c, p, (changed & (1U << 4)) != 0);
    encode_attributes(*c, p, changed);
    c->last = p;
    c->last.gps_time_change = (changed & (1U << 4)) != 0;
    return current_;
}

void Point14Encoder::encode_returns(Context& c, const Fields& p, std::uint32_t changed) {
    ArithmeticEncoder& enc = layers_[kXy].encoder;
    const unsigned last_n = c.last.number_of_returns;
    const unsigned last_r = c.last.return_number;
    if ((changed & (1U << 2)) != 0) {
        enc.encode_symbol(c.lazy(c.number_of_returns_models[last_n], 16), p.number_of_returns);
    }
    if ((changed & 3U) == 3U) {
        if ((changed & (1U << 4)) != 0) {
            enc.encode_symbol(c.lazy(c.return_number_models[last_r], 16), p.return_number);
        } else {
            // r = (last_r + sym + 2) % 16
            enc.encode_symbol(c.return_number_gps_same, (p.return_number + 16 - last_r - 2) % 16);
        }
    }
}

void Point14Encoder::encode_xyz(Context& c, const Fields& p, bool gps_change) {
    ArithmeticEncoder& enc = layers_[kXy].encoder;
    const unsigned n = p.number_of_returns;
    const unsigned r = p.return_number;
    const unsigned m = point14::kReturnMap6[n][r];
    const std::uint32_t single = n == 1 ? 1U : 0U;
    const unsigned median = (m << 1U) | (gps_change ? 1U : 0U);
    const std::int32_t diff_x = wrap_sub(p.x, c.last.x);
    c.dx.compress(enc, c.x_median[median].get(), diff_x, single);
    c.x_median[median].add(diff_x);
    const std::uint32_t kx = c.dx.k();
    const std::int32_t diff_y = wrap_sub(p.y, c.last.y);
    c.dy.compress(enc, c.y_median[median].get(), diff_y, single + (kx < 20 ? (kx & ~1U) : 20U));
    c.y_median[median].add(diff_y);
    const std::uint32_t kxy = (c.dx.k() + c.dy.k()) / 2;
    const unsigned l = point14::return_level(n, r);
    c.dz.compress(layers_[kZ].encoder, c.last_z[l], p.z, single + (kxy < 18 ? (kxy & ~1U) : 18U));
    c.last_z[l] = p.z;
}

void Point14Encoder::encode_attributes(Context& c, const Fields& p, std::uint32_t changed) {
    const unsigned gps_change = (changed >> 4U) & 1U;
    const Fields& last = c.last;
    const unsigned r = p.return_number;
    const unsigned cpr = (r == 1 ? 2U : 0U) + (r >= p.number_of_returns ? 1U : 0U);

    EncodeLayer& cl = layers_[kClassification];
    cl.changed |= p.classification != last.classification;
    const unsigned ccc = ((last.classification & 0x1FU) << 1U) + (cpr == 3 ? 1U : 0U);
    cl.encoder.encode_symbol(c.lazy(c.classification_models[ccc], 256), p.classification);

    EncodeLayer& fl = layers_[kFlags];
    fl.changed |= p.flags() != last.flags();
    fl.encoder.encode_symbol(c.lazy(c.flags_models[last.flags()], 64), p.flags());

    EncodeLayer& il = layers_[kIntensity];
    il.changed |= p.intensity != last.intensity;
    std::uint16_t& last_intensity = c.last_intensity[(cpr << 1U) | gps_change];
    c.intensity_ic.compress(il.encoder, last_intensity, p.intensity, cpr);
    last_intensity = p.intensity;

    if ((changed & (1U << 3)) != 0) {
        layers_[kScanAngle].changed = true;
        c.scan_angle_ic.compress(layers_[kScanAngle].encoder, last.scan_angle, p.scan_angle,
                                 gps_change);
    }

    EncodeLayer& ul = layers_[kUserData];
    ul.changed |= p.user_data != last.user_data;
    ul.encoder.encode_symbol(c.lazy(c.user_data_models[last.user_data / 4], 256), p.user_data);

    if ((changed & (1U << 5)) != 0) {
        layers_[kPointSource].changed = true;
        c.point_source_ic.compress(layers_[kPointSource].encoder, last.point_source,
                                   p.point_source);
    }
    if (gps_change != 0) {
        layers_[kGpsTime].changed = true;
        encode_gps_time(c, layers_[kGpsTime].encoder, p.gps_time);
    }
}

namespace {

/// The first of the other three sequences (1-3 steps from `last`) that `time_bits` lies within
/// 32 bits of, or 0.
[[nodiscard]] unsigned other_sequence(const std::array<std::uint64_t, 4>& gps, unsigned last,
                                      std::uint64_t time_bits) {
    for (unsigned i = 1; i < 4; ++i) {
        const auto d = static_cast<std::int64_t>(time_bits - gps[(last + i) & 3U]);
        if (d == static_cast<std::int32_t>(d)) {
            return i;
        }
    }
    return 0;
}

}  // namespace

void Point14Encoder::encode_gps_time(Context& c, ArithmeticEncoder& enc, std::uint64_t time_bits) {
    // A switch to another sequence is followed by that sequence's code (at most one switch:
    // the time then lies within 32 bits of the sequence).
    for (;;) {
        const unsigned s = c.gps_last;
        const auto d64 = static_cast<std::int64_t>(time_bits - c.gps[s]);
        const auto d32 = static_cast<std::int32_t>(d64);
        const bool fits = d64 == d32;
        const bool zero_diff = c.gps_diff[s] == 0;
        ArithmeticModel& model = zero_diff ? c.gps_0diff : c.gps_multi;
        if (fits && zero_diff) {
            enc.encode_symbol(model, 0);
            c.gps_ic.compress(enc, 0, d32, 0);
            c.gps_diff[s] = d32;
            c.gps_extreme[s] = 0;
        } else if (fits) {
            encode_gps_difference(c, enc, d32);
        } else if (const unsigned i = other_sequence(c.gps, s, time_bits); i != 0) {
            enc.encode_symbol(model, zero_diff ? i + 1 : kGpsCodeFull + i);
            c.gps_last = (s + i) & 3U;
            continue;
        } else {
            enc.encode_symbol(model, zero_diff ? 1U : kGpsCodeFull);
            encode_full_gps_time(c, enc, time_bits);
        }
        c.gps[c.gps_last] = time_bits;
        return;
    }
}

void Point14Encoder::encode_full_gps_time(Context& c, ArithmeticEncoder& enc,
                                          std::uint64_t time_bits) {
    c.gps_ic.compress(enc, static_cast<std::int32_t>(c.gps[c.gps_last] >> 32U),
                      static_cast<std::int32_t>(time_bits >> 32U), 8);
    enc.write_int(static_cast<std::uint32_t>(time_bits));
    c.gps_next = (c.gps_next + 1) & 3U;
    c.gps_last = c.gps_next;
    c.gps_diff[c.gps_last] = 0;
    c.gps_extreme[c.gps_last] = 0;
}

void Point14Encoder::encode_gps_difference(Context& c, ArithmeticEncoder& enc, std::int32_t diff) {
    const unsigned s = c.gps_last;
    const std::int32_t last = c.gps_diff[s];
    const std::int32_t multi = quantize(static_cast<float>(diff) / static_cast<float>(last));
    bool extreme = false;
    if (multi == 1) {
        enc.encode_symbol(c.gps_multi, 1);
        c.gps_ic.compress(enc, last, diff, 1);
        c.gps_extreme[s] = 0;
    } else if (multi > 0 && multi < kGpsMulti) {
        enc.encode_symbol(c.gps_multi, static_cast<std::uint32_t>(multi));
        c.gps_ic.compress(enc, wrap_mul(multi, last), diff, multi < 10 ? 2 : 3);
    } else if (multi >= kGpsMulti) {
        enc.encode_symbol(c.gps_multi, static_cast<std::uint32_t>(kGpsMulti));
        c.gps_ic.compress(enc, wrap_mul(kGpsMulti, last), diff, 4);
        extreme = true;
    } else if (multi < 0 && multi > kGpsMultiMinus) {
        enc.encode_symbol(c.gps_multi, static_cast<std::uint32_t>(kGpsMulti - multi));
        c.gps_ic.compress(enc, wrap_mul(multi, last), diff, 5);
    } else if (multi < 0) {
        enc.encode_symbol(c.gps_multi, static_cast<std::uint32_t>(kGpsMulti - kGpsMultiMinus));
        c.gps_ic.compress(enc, wrap_mul(kGpsMultiMinus, last), diff, 6);
        extreme = true;
    } else {
        enc.encode_symbol(c.gps_multi, 0);
        c.gps_ic.compress(enc, 0, diff, 7);
        extreme = true;
    }
    if (extreme && ++c.gps_extreme[s] > 3) {
        c.gps_diff[s] = diff;
        c.gps_extreme[s] = 0;
    }
}

void Point14Encoder::finish(std::vector<std::span<const std::uint8_t>>& layers) {
    for (std::size_t i = 0; i < kLayers; ++i) {
        // LASzip always writes the XY and Z layers.
        layers.push_back(layers_[i].finish(i == kXy || i == kZ));
    }
}

}  // namespace beamtrace::laz
