// The version-1 point-wise item decoders.
#include "laz/items_v1.hpp"

#include <algorithm>

namespace beamtrace::laz {
namespace {

/// The median of three, with the format's tie rules.
std::int32_t median3(const std::array<std::int32_t, 3>& v) {
    if (v[0] < v[1]) {
        if (v[1] < v[2]) {
            return v[1];
        }
        return v[0] < v[2] ? v[2] : v[0];
    }
    if (v[0] < v[2]) {
        return v[0];
    }
    return v[1] < v[2] ? v[2] : v[1];
}

std::uint32_t cap(std::uint32_t k, std::uint32_t limit) {
    return std::min(k, limit);
}

}  // namespace

Point10DecoderV1::Point10DecoderV1()
    : dx_(32),
      dy_(32, 20),
      z_(32, 20),
      intensity_(16),
      scan_angle_(8, 2),
      point_source_(16),
      changed_(64, false),
      flags_(256, false),
      classification_(256, false),
      user_data_(256, false) {}

void Point10DecoderV1::init(const std::uint8_t* item) {
    for (IntegerCompressor* ic : {&dx_, &dy_, &z_, &intensity_, &scan_angle_, &point_source_}) {
        ic->init_decompressor();
    }
    changed_.init();
    flags_.reset();
    classification_.reset();
    user_data_.reset();
    last_ = Point10::load(item);
    last_dx_.fill(0);
    last_dy_.fill(0);
    slot_ = 0;
}

void Point10DecoderV1::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    const std::int32_t dx = dx_.decompress(dec, median3(last_dx_));
    last_.x = wrap_add(last_.x, dx);
    const std::uint32_t kx = dx_.k();
    const std::int32_t dy = dy_.decompress(dec, median3(last_dy_), cap(kx, 19));
    last_.y = wrap_add(last_.y, dy);
    const std::uint32_t kz = (kx + dy_.k()) / 2;
    last_.z = z_.decompress(dec, last_.z, cap(kz, 19));
    decode_changed(dec, kz);
    last_dx_[slot_] = dx;
    last_dy_[slot_] = dy;
    slot_ = slot_ == 2 ? 0 : slot_ + 1;
    last_.store(item);
}

void Point10DecoderV1::decode_changed(ArithmeticDecoder& dec, std::uint32_t kz) {
    const std::uint32_t changed = dec.decode_symbol(changed_);
    if ((changed & 32U) != 0) {
        last_.intensity = static_cast<std::uint16_t>(intensity_.decompress(dec, last_.intensity));
    }
    if ((changed & 16U) != 0) {
        last_.flags = static_cast<std::uint8_t>(dec.decode_symbol(flags_[last_.flags]));
    }
    if ((changed & 8U) != 0) {
        last_.classification =
            static_cast<std::uint8_t>(dec.decode_symbol(classification_[last_.classification]));
    }
    if ((changed & 4U) != 0) {
        last_.scan_angle = static_cast<std::uint8_t>(
            scan_angle_.decompress(dec, last_.scan_angle, kz < 3 ? 1 : 0));
    }
    if ((changed & 2U) != 0) {
        last_.user_data = static_cast<std::uint8_t>(dec.decode_symbol(user_data_[last_.user_data]));
    }
    if ((changed & 1U) != 0) {
        last_.point_source =
            static_cast<std::uint16_t>(point_source_.decompress(dec, last_.point_source));
    }
}

namespace {
constexpr std::uint32_t kMultiMax = 512;
}  // namespace

Gpstime11DecoderV1::Gpstime11DecoderV1()
    : multi_(kMultiMax, false), zero_diff_(3, false), ic_(32, 6) {}

void Gpstime11DecoderV1::init(const std::uint8_t* item) {
    multi_.init();
    zero_diff_.init();
    ic_.init_decompressor();
    time_ = load_u64(item);
    diff_ = 0;
    extreme_ = 0;
}

void Gpstime11DecoderV1::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    if (diff_ == 0) {
        const std::uint32_t multi = dec.decode_symbol(zero_diff_);
        if (multi == 1) {
            diff_ = ic_.decompress(dec, 0, 0);
            time_ += static_cast<std::uint64_t>(static_cast<std::int64_t>(diff_));
        } else if (multi == 2) {
            time_ = dec.read_int64();
        }
    } else {
        const std::uint32_t multi = dec.decode_symbol(multi_);
        if (multi < kMultiMax - 2) {
            decode_multiplied(dec, multi);
        } else if (multi == kMultiMax - 2) {
            time_ = dec.read_int64();
        }
    }
    store_u64(item, time_);
}

void Gpstime11DecoderV1::decode_multiplied(ArithmeticDecoder& dec, std::uint32_t multi) {
    std::int32_t d = 0;
    const auto m = static_cast<std::int32_t>(multi);
    if (multi == 1) {
        d = ic_.decompress(dec, diff_, 1);
        diff_ = d;
        extreme_ = 0;
    } else if (multi == 0) {
        d = ic_.decompress(dec, diff_ / 4, 2);
        if (++extreme_ > 3) {
            diff_ = d;
            extreme_ = 0;
        }
    } else if (multi < 10) {
        d = ic_.decompress(dec, wrap_mul(m, diff_), 3);
    } else if (multi < 50) {
        d = ic_.decompress(dec, wrap_mul(m, diff_), 4);
    } else {
        d = ic_.decompress(dec, wrap_mul(m, diff_), 5);
        if (multi == kMultiMax - 3 && ++extreme_ > 3) {
            diff_ = d;
            extreme_ = 0;
        }
    }
    time_ += static_cast<std::uint64_t>(static_cast<std::int64_t>(d));
}

Rgb12DecoderV1::Rgb12DecoderV1() : used_(64, false), ic_(8, 6) {}

void Rgb12DecoderV1::init(const std::uint8_t* item) {
    used_.init();
    ic_.init_decompressor();
    std::copy(item, item + 6, last_.begin());
}

void Rgb12DecoderV1::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    // Bit b of the mask: byte b of the item (low then high byte of red, green, blue) changed.
    const std::uint32_t sym = dec.decode_symbol(used_);
    for (std::uint32_t b = 0; b < 6; ++b) {
        if ((sym & (1U << b)) != 0) {
            last_[b] = static_cast<std::uint8_t>(ic_.decompress(dec, last_[b], b));
        }
        item[b] = last_[b];
    }
}

ByteDecoderV1::ByteDecoderV1(std::size_t count)
    : ic_(8, static_cast<std::uint32_t>(count)), last_(count, 0) {}

void ByteDecoderV1::init(const std::uint8_t* item) {
    ic_.init_decompressor();
    std::copy(item, item + last_.size(), last_.begin());
}

void ByteDecoderV1::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    for (std::size_t i = 0; i < last_.size(); ++i) {
        last_[i] =
            static_cast<std::uint8_t>(ic_.decompress(dec, last_[i], static_cast<std::uint32_t>(i)));
        item[i] = last_[i];
    }
}

Wavepacket13CodecV1::Wavepacket13CodecV1(bool compress)
    : index_(256, compress),
      offset_kind_{ArithmeticModel(4, compress), ArithmeticModel(4, compress),
                   ArithmeticModel(4, compress), ArithmeticModel(4, compress)},
      offset_diff_(32),
      packet_size_(32),
      return_point_(32),
      xyz_(32, 3),
      compress_(compress) {}

void Wavepacket13CodecV1::init(const std::uint8_t* item) {
    index_.init();
    for (ArithmeticModel& m : offset_kind_) {
        m.init();
    }
    for (IntegerCompressor* ic : {&offset_diff_, &packet_size_, &return_point_, &xyz_}) {
        if (compress_) {
            ic->init_compressor();
        } else {
            ic->init_decompressor();
        }
    }
    offset_ = load_u64(item + 1);
    size_ = load_u32(item + 9);
    for (std::size_t i = 0; i < 4; ++i) {
        point_xyz_[i] = static_cast<std::int32_t>(load_u32(item + 13 + 4 * i));
    }
    last_offset_diff_ = 0;
    last_kind_ = 0;
}

// The offset's kind: 0 the same as the last, 1 right after the last packet, 2 a 32-bit
// difference, 3 a full 64-bit offset.
void Wavepacket13CodecV1::decode(ArithmeticDecoder& dec, std::uint8_t* item) {
    item[0] = static_cast<std::uint8_t>(dec.decode_symbol(index_));
    last_kind_ = dec.decode_symbol(offset_kind_[last_kind_]);
    if (last_kind_ == 1) {
        offset_ += size_;
    } else if (last_kind_ == 2) {
        last_offset_diff_ = offset_diff_.decompress(dec, last_offset_diff_);
        offset_ += static_cast<std::uint64_t>(static_cast<std::int64_t>(last_offset_diff_));
    } else if (last_kind_ == 3) {
        offset_ = dec.read_int64();
    }
    size_ =
        static_cast<std::uint32_t>(packet_size_.decompress(dec, static_cast<std::int32_t>(size_)));
    point_xyz_[0] = return_point_.decompress(dec, point_xyz_[0]);
    for (std::uint32_t i = 1; i < 4; ++i) {
        point_xyz_[i] = xyz_.decompress(dec, point_xyz_[i], i - 1);
    }
    store_u64(item + 1, offset_);
    store_u32(item + 9, size_);
    for (std::size_t i = 0; i < 4; ++i) {
        store_u32(item + 13 + 4 * i, static_cast<std::uint32_t>(point_xyz_[i]));
    }
}

void Wavepacket13CodecV1::encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
    enc.encode_symbol(index_, item[0]);
    const std::uint64_t offset = load_u64(item + 1);
    const auto diff64 = static_cast<std::int64_t>(offset - offset_);
    const auto diff = static_cast<std::int32_t>(diff64);
    std::uint32_t kind = 3;
    if (diff64 == diff) {
        kind = diff == 0 ? 0 : (diff64 == static_cast<std::int64_t>(size_) ? 1 : 2);
    }
    enc.encode_symbol(offset_kind_[last_kind_], kind);
    last_kind_ = kind;
    if (kind == 2) {
        offset_diff_.compress(enc, last_offset_diff_, diff);
        last_offset_diff_ = diff;
    } else if (kind == 3) {
        enc.write_int64(offset);
    }
    offset_ = offset;
    const std::uint32_t size = load_u32(item + 9);
    packet_size_.compress(enc, static_cast<std::int32_t>(size_), static_cast<std::int32_t>(size));
    size_ = size;
    for (std::uint32_t i = 0; i < 4; ++i) {
        const auto v = static_cast<std::int32_t>(load_u32(item + 13 + 4 * i));
        if (i == 0) {
            return_point_.compress(enc, point_xyz_[0], v);
        } else {
            xyz_.compress(enc, point_xyz_[i], v, i - 1);
        }
        point_xyz_[i] = v;
    }
}

}  // namespace beamtrace::laz
