#include "beamtrace/io/las_extra_bytes.hpp"

#include <algorithm>
#include <cstring>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

namespace {

// Field offsets in a descriptor (LAS 1.4 R15 Table 24).
constexpr std::size_t kType = 2, kOptions = 3, kName = 4, kNoData = 40, kMin = 64, kMax = 88,
                      kScale = 112, kOffset = 136, kDescription = 160, kTextBytes = 32;

bool is_signed(LasExtraType t) {
    return t == LasExtraType::i8 || t == LasExtraType::i16 || t == LasExtraType::i32 ||
           t == LasExtraType::i64;
}
bool is_float(LasExtraType t) {
    return t == LasExtraType::f32 || t == LasExtraType::f64;
}

/// A no_data, min or max value in its 8-byte slot, as the type says.
void store_any(std::uint8_t* at, LasExtraType t, double v) {
    if (is_float(t)) {
        std::memcpy(at, &v, 8);
    } else if (is_signed(t)) {
        const auto i = static_cast<std::int64_t>(v);
        std::memcpy(at, &i, 8);
    } else {
        const auto u = static_cast<std::uint64_t>(v);
        std::memcpy(at, &u, 8);
    }
}

double load_any(const std::uint8_t* at, LasExtraType t) {
    if (is_float(t)) {
        double v = 0;
        std::memcpy(&v, at, 8);
        return v;
    }
    if (is_signed(t)) {
        std::int64_t i = 0;
        std::memcpy(&i, at, 8);
        return static_cast<double>(i);
    }
    std::uint64_t u = 0;
    std::memcpy(&u, at, 8);
    return static_cast<double>(u);
}

template <class T>
double load_raw(const std::uint8_t* at) {
    T v{};
    std::memcpy(&v, at, sizeof(T));
    return static_cast<double>(v);
}

double raw_value(const std::uint8_t* at, LasExtraType t) {
    switch (t) {
        case LasExtraType::u8:
            return load_raw<std::uint8_t>(at);
        case LasExtraType::i8:
            return load_raw<std::int8_t>(at);
        case LasExtraType::u16:
            return load_raw<std::uint16_t>(at);
        case LasExtraType::i16:
            return load_raw<std::int16_t>(at);
        case LasExtraType::u32:
            return load_raw<std::uint32_t>(at);
        case LasExtraType::i32:
            return load_raw<std::int32_t>(at);
        case LasExtraType::u64:
            return load_raw<std::uint64_t>(at);
        case LasExtraType::i64:
            return load_raw<std::int64_t>(at);
        case LasExtraType::f32:
            return load_raw<float>(at);
        case LasExtraType::f64:
            return load_raw<double>(at);
        case LasExtraType::undocumented:
            break;
    }
    return 0.0;
}

std::string text(const std::uint8_t* at) {
    const auto* c = reinterpret_cast<const char*>(at);
    return {c, static_cast<std::size_t>(std::find(c, c + kTextBytes, '\0') - c)};
}

LasExtraBytesDescriptor parse_descriptor(const std::uint8_t* d) {
    LasExtraBytesDescriptor e;
    e.data_type = static_cast<LasExtraType>(d[kType]);
    e.options = d[kOptions];
    e.name = text(d + kName);
    e.no_data = load_any(d + kNoData, e.data_type);
    e.min = load_any(d + kMin, e.data_type);
    e.max = load_any(d + kMax, e.data_type);
    std::memcpy(&e.scale, d + kScale, 8);
    std::memcpy(&e.offset, d + kOffset, 8);
    e.description = text(d + kDescription);
    return e;
}

}  // namespace

std::size_t las_extra_type_size(LasExtraType type) {
    switch (type) {
        case LasExtraType::u8:
        case LasExtraType::i8:
            return 1;
        case LasExtraType::u16:
        case LasExtraType::i16:
            return 2;
        case LasExtraType::u32:
        case LasExtraType::i32:
        case LasExtraType::f32:
            return 4;
        case LasExtraType::u64:
        case LasExtraType::i64:
        case LasExtraType::f64:
            return 8;
        case LasExtraType::undocumented:
            break;
    }
    return 0;
}

LasVlr las_extra_bytes_vlr(std::span<const LasExtraBytesDescriptor> descriptors) {
    LasVlr vlr;
    vlr.user_id = "LASF_Spec";
    vlr.record_id = 4;
    vlr.description = "Extra Bytes";
    vlr.data.assign(descriptors.size() * kLasExtraBytesDescriptorBytes, 0);
    std::uint8_t* d = vlr.data.data();
    for (const LasExtraBytesDescriptor& e : descriptors) {
        if (e.name.size() >= kTextBytes || e.description.size() >= kTextBytes ||
            e.data_type == LasExtraType::undocumented ||
            static_cast<int>(e.data_type) > static_cast<int>(LasExtraType::f64)) {
            throw ConfigError("LAS extra bytes '" + e.name +
                              "': the name and description take at most 31 characters and the "
                              "type must be one of 1 to 10");
        }
        d[kType] = static_cast<std::uint8_t>(e.data_type);
        d[kOptions] = e.options;
        std::memcpy(d + kName, e.name.data(), e.name.size());
        store_any(d + kNoData, e.data_type, e.no_data);
        store_any(d + kMin, e.data_type, e.min);
        store_any(d + kMax, e.data_type, e.max);
        std::memcpy(d + kScale, &e.scale, 8);
        std::memcpy(d + kOffset, &e.offset, 8);
        std::memcpy(d + kDescription, e.description.data(), e.description.size());
        d += kLasExtraBytesDescriptorBytes;
    }
    return vlr;
}

std::vector<LasExtraBytesDescriptor> las_extra_bytes_descriptors(std::span<const LasVlr> vlrs) {
    std::vector<LasExtraBytesDescriptor> out;
    for (const LasVlr& v : vlrs) {
        if (v.user_id != "LASF_Spec" || v.record_id != 4) {
            continue;
        }
        if (v.data.size() % kLasExtraBytesDescriptorBytes != 0) {
            throw InputError("LAS Extra Bytes VLR", std::to_string(v.data.size()) +
                                                        " bytes is not a whole number of "
                                                        "192-byte descriptors");
        }
        for (std::size_t at = 0; at < v.data.size(); at += kLasExtraBytesDescriptorBytes) {
            out.push_back(parse_descriptor(v.data.data() + at));
        }
    }
    return out;
}

std::size_t las_extra_bytes_size(std::span<const LasExtraBytesDescriptor> descriptors) {
    std::size_t n = 0;
    for (const auto& e : descriptors) {
        // Undocumented bytes: the options byte counts them.
        n += e.data_type == LasExtraType::undocumented ? e.options
                                                       : las_extra_type_size(e.data_type);
    }
    return n;
}

double las_extra_bytes_value(std::span<const LasExtraBytesDescriptor> descriptors,
                             std::size_t index, std::span<const std::uint8_t> extra) {
    const std::size_t at = las_extra_bytes_size(descriptors.first(index));
    const LasExtraBytesDescriptor& e = descriptors[index];
    if (at + las_extra_type_size(e.data_type) > extra.size()) {
        throw InputError("LAS extra bytes", "field '" + e.name + "' lies past the point's " +
                                                std::to_string(extra.size()) + " extra bytes");
    }
    double v = raw_value(extra.data() + at, e.data_type);
    if ((e.options & LasExtraBytesDescriptor::kScale) != 0) {
        v *= e.scale;
    }
    if ((e.options & LasExtraBytesDescriptor::kOffset) != 0) {
        v += e.offset;
    }
    return v;
}

}  // namespace beamtrace
