// POINT10 version 2.
#include "laz/items_v2.hpp"

namespace beamtrace::laz {
namespace {

struct Contexts {
    std::uint32_t m;       ///< return context, 0-15
    std::uint32_t l;       ///< return level, 0-7
    std::uint32_t single;  ///< 1 for a single return (n == 1)
};

Contexts contexts_of(const Point10& p) {
    const unsigned r = p.return_number();
    const unsigned n = p.number_of_returns();
    return {kReturnContext[n][r], kReturnLevel[n][r], n == 1 ? 1U : 0U};
}

/// The context of y from the k of x, and of z from the mean k of x and y (even values only).
std::uint32_t k_context(std::uint32_t k, std::uint32_t cap) {
    return k < cap ? (k & ~1U) : cap;
}

}  // namespace

Point10CodecV2::Point10CodecV2(bool compress)
    : changed_(64, compress),
      intensity_(16, 4),
      scan_angle_{ArithmeticModel(256, compress), ArithmeticModel(256, compress)},
      point_source_(16),
      flags_(256, compress),
      classification_(256, compress),
      user_data_(256, compress),
      dx_(32, 2),
      dy_(32, 22),
      z_(32, 20),
      compress_(compress) {}

void Point10CodecV2::init(const std::uint8_t* item) {
    changed_.init();
    scan_angle_[0].init();
    scan_angle_[1].init();
    flags_.reset();
    classification_.reset();
    user_data_.reset();
    for (IntegerCompressor* ic : {&intensity_, &point_source_, &dx_, &dy_, &z_}) {
        if (compress_) {
            ic->init_compressor();
        } else {
            ic->init_decompressor();
        }
    }
    for (std::size_t i = 0; i < 16; ++i) {
        x_median_[i].init();
        y_median_[i].init();
    }
    last_intensity_.fill(0);
    last_height_.fill(0);
    last_ = Point10::load(item);
    last_.intensity = 0;  // the intensity is predicted per return context, from zero
}

void Point10CodecV2::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    const std::uint32_t changed = dec.decode_symbol(changed_);
    if ((changed & 32U) != 0) {
        last_.flags = static_cast<std::uint8_t>(dec.decode_symbol(flags_[last_.flags]));
    }
    const Contexts c = contexts_of(last_);
    if (changed != 0) {
        if ((changed & 16U) != 0) {
            last_.intensity = static_cast<std::uint16_t>(
                intensity_.decompress(dec, last_intensity_[c.m], c.m < 3 ? c.m : 3));
            last_intensity_[c.m] = last_.intensity;
        } else {
            last_.intensity = last_intensity_[c.m];
        }
        if ((changed & 8U) != 0) {
            last_.classification =
                static_cast<std::uint8_t>(dec.decode_symbol(classification_[last_.classification]));
        }
        if ((changed & 4U) != 0) {
            const std::uint32_t d = dec.decode_symbol(scan_angle_[last_.scan_direction()]);
            last_.scan_angle = static_cast<std::uint8_t>(d + last_.scan_angle);
        }
        if ((changed & 2U) != 0) {
            last_.user_data =
                static_cast<std::uint8_t>(dec.decode_symbol(user_data_[last_.user_data]));
        }
        if ((changed & 1U) != 0) {
            last_.point_source =
                static_cast<std::uint16_t>(point_source_.decompress(dec, last_.point_source));
        }
    }
    const std::int32_t dx = dx_.decompress(dec, x_median_[c.m].get(), c.single);
    last_.x = wrap_add(last_.x, dx);
    x_median_[c.m].add(dx);
    const std::int32_t dy =
        dy_.decompress(dec, y_median_[c.m].get(), c.single + k_context(dx_.k(), 20));
    last_.y = wrap_add(last_.y, dy);
    y_median_[c.m].add(dy);
    const std::uint32_t kz = (dx_.k() + dy_.k()) / 2;
    last_.z = z_.decompress(dec, last_height_[c.l], c.single + k_context(kz, 18));
    last_height_[c.l] = last_.z;
    last_.store(item);
}

void Point10CodecV2::encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
    const Point10 p = Point10::load(item);
    const Contexts c = contexts_of(p);
    const std::uint32_t changed =
        (p.flags != last_.flags ? 32U : 0U) | (p.intensity != last_intensity_[c.m] ? 16U : 0U) |
        (p.classification != last_.classification ? 8U : 0U) |
        (p.scan_angle != last_.scan_angle ? 4U : 0U) | (p.user_data != last_.user_data ? 2U : 0U) |
        (p.point_source != last_.point_source ? 1U : 0U);
    enc.encode_symbol(changed_, changed);
    if ((changed & 32U) != 0) {
        enc.encode_symbol(flags_[last_.flags], p.flags);
    }
    if ((changed & 16U) != 0) {
        intensity_.compress(enc, last_intensity_[c.m], p.intensity, c.m < 3 ? c.m : 3);
        last_intensity_[c.m] = p.intensity;
    }
    if ((changed & 8U) != 0) {
        enc.encode_symbol(classification_[last_.classification], p.classification);
    }
    if ((changed & 4U) != 0) {
        enc.encode_symbol(scan_angle_[p.scan_direction()],
                          static_cast<std::uint8_t>(p.scan_angle - last_.scan_angle));
    }
    if ((changed & 2U) != 0) {
        enc.encode_symbol(user_data_[last_.user_data], p.user_data);
    }
    if ((changed & 1U) != 0) {
        point_source_.compress(enc, last_.point_source, p.point_source);
    }
    const std::int32_t dx = wrap_sub(p.x, last_.x);
    dx_.compress(enc, x_median_[c.m].get(), dx, c.single);
    x_median_[c.m].add(dx);
    const std::int32_t dy = wrap_sub(p.y, last_.y);
    dy_.compress(enc, y_median_[c.m].get(), dy, c.single + k_context(dx_.k(), 20));
    y_median_[c.m].add(dy);
    const std::uint32_t kz = (dx_.k() + dy_.k()) / 2;
    z_.compress(enc, last_height_[c.l], p.z, c.single + k_context(kz, 18));
    last_height_[c.l] = p.z;
    last_ = p;
}

}  // namespace beamtrace::laz
