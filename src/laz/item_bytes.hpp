// Little-endian loads and stores of the record fields that the item codecs work on, and the
// POINT10 record unpacked (the layout of LAS point formats 0-5, bytes 0-19).
#pragma once

#include <cstdint>
#include <cstring>

namespace beamtrace::laz {

/// A value of type T stored little-endian at p (x86-64 and every LAS reader's host order).
template <typename T>
[[nodiscard]] T load(const std::uint8_t* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
}

/// Stores `value` at p, little-endian.
template <typename T>
void store(std::uint8_t* p, T value) {
    std::memcpy(p, &value, sizeof(T));
}

inline std::uint16_t load_u16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
inline std::uint32_t load_u32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
           (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
inline std::uint64_t load_u64(const std::uint8_t* p) {
    return static_cast<std::uint64_t>(load_u32(p)) |
           (static_cast<std::uint64_t>(load_u32(p + 4)) << 32);
}
inline void store_u16(std::uint8_t* p, std::uint16_t v) {
    p[0] = static_cast<std::uint8_t>(v);
    p[1] = static_cast<std::uint8_t>(v >> 8);
}
inline void store_u32(std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) {
        p[i] = static_cast<std::uint8_t>(v >> (8 * i));
    }
}
inline void store_u64(std::uint8_t* p, std::uint64_t v) {
    store_u32(p, static_cast<std::uint32_t>(v));
    store_u32(p + 4, static_cast<std::uint32_t>(v >> 32));
}

/// Wrapping int32 arithmetic (the format's sums and products wrap; C++ signed overflow may not).
inline std::int32_t wrap_add(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b));
}
inline std::int32_t wrap_sub(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
}
inline std::int32_t wrap_mul(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) * static_cast<std::uint32_t>(b));
}

/// The 20 bytes of a POINT10 item, unpacked.
struct Point10 {
    std::int32_t x = 0;
    std::int32_t y = 0;
    std::int32_t z = 0;
    std::uint16_t intensity = 0;
    std::uint8_t flags = 0;  ///< return number (bits 0-2), number of returns (3-5), scan dir, edge
    std::uint8_t classification = 0;
    std::uint8_t scan_angle = 0;
    std::uint8_t user_data = 0;
    std::uint16_t point_source = 0;

    [[nodiscard]] unsigned return_number() const { return flags & 7U; }
    [[nodiscard]] unsigned number_of_returns() const { return (flags >> 3) & 7U; }
    [[nodiscard]] unsigned scan_direction() const { return (flags >> 6) & 1U; }

    static Point10 load(const std::uint8_t* p) {
        Point10 r;
        r.x = static_cast<std::int32_t>(load_u32(p));
        r.y = static_cast<std::int32_t>(load_u32(p + 4));
        r.z = static_cast<std::int32_t>(load_u32(p + 8));
        r.intensity = load_u16(p + 12);
        r.flags = p[14];
        r.classification = p[15];
        r.scan_angle = p[16];
        r.user_data = p[17];
        r.point_source = load_u16(p + 18);
        return r;
    }
    void store(std::uint8_t* p) const {
        store_u32(p, static_cast<std::uint32_t>(x));
        store_u32(p + 4, static_cast<std::uint32_t>(y));
        store_u32(p + 8, static_cast<std::uint32_t>(z));
        store_u16(p + 12, intensity);
        p[14] = flags;
        p[15] = classification;
        p[16] = scan_angle;
        p[17] = user_data;
        store_u16(p + 18, point_source);
    }
};

}  // namespace beamtrace::laz
