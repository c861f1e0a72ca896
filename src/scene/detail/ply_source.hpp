// Value readers for the data section of a PLY file: one for ascii, one for binary (either byte
// order). Both offer the same interface so that the element readers are written once.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "beamtrace/core/error.hpp"
#include "scene/detail/ply_header.hpp"
#include "text/text_scan.hpp"

namespace beamtrace::detail {

/// Reads whitespace-separated numbers; malformed tokens throw with the line number.
class PlyAsciiSource {
  public:
    PlyAsciiSource(std::string_view data, long first_line, const std::string& path)
        : cursor_(data, first_line), path_(path), size_(data.size()) {}

    /// False at the end of the data.
    [[nodiscard]] bool read_real(PlyType /*type*/, double& out) {
        const std::string_view token = cursor_.next();
        if (token.empty()) {
            return false;
        }
        if (!parse_number(token, out)) {
            fail("malformed number '" + std::string(token) + "'");
        }
        return true;
    }

    /// Reads a value of an integer type (list counts and indices).
    [[nodiscard]] bool read_integer(PlyType /*type*/, std::int64_t& out) {
        const std::string_view token = cursor_.next();
        if (token.empty()) {
            return false;
        }
        if (parse_number(token, out)) {
            return true;
        }
        // Some writers print integers as "3.0"; accept whole numbers written that way.
        double value = 0.0;
        if (!parse_number(token, value) || !(std::fabs(value) < 9.0e18) ||
            std::trunc(value) != value) {
            fail("malformed integer '" + std::string(token) + "'");
        }
        out = static_cast<std::int64_t>(value);
        return true;
    }

    [[nodiscard]] bool skip(PlyType /*type*/) { return !cursor_.next().empty(); }

    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(path_, cursor_.line(), what);
    }
    /// An upper bound of the bytes left (for reserving memory).
    [[nodiscard]] std::size_t size() const { return size_; }

  private:
    TextCursor cursor_;
    const std::string& path_;
    std::size_t size_;
};

/// Reads fixed-size values in either byte order.
class PlyBinarySource {
  public:
    PlyBinarySource(std::string_view data, bool big_endian, const std::string& path)
        : pos_(data.data()),
          end_(data.data() + data.size()),
          swap_(big_endian != (std::endian::native == std::endian::big)),
          path_(path) {}

    [[nodiscard]] bool read_real(PlyType type, double& out) {
        switch (type) {
            case PlyType::float32: {
                float v = 0.0f;
                if (!load(v)) {
                    return false;
                }
                out = static_cast<double>(v);
                return true;
            }
            case PlyType::float64:
                return load(out);
            default: {
                std::int64_t v = 0;
                if (!read_integer(type, v)) {
                    return false;
                }
                out = static_cast<double>(v);
                return true;
            }
        }
    }

    /// Reads a value of an integer type (the header check guarantees `type` is one).
    [[nodiscard]] bool read_integer(PlyType type, std::int64_t& out) {
        switch (type) {
            case PlyType::int8:
                return load_as<std::int8_t>(out);
            case PlyType::uint8:
                return load_as<std::uint8_t>(out);
            case PlyType::int16:
                return load_as<std::int16_t>(out);
            case PlyType::uint16:
                return load_as<std::uint16_t>(out);
            case PlyType::int32:
                return load_as<std::int32_t>(out);
            case PlyType::uint32:
                return load_as<std::uint32_t>(out);
            case PlyType::float32:
            case PlyType::float64:
                break;
        }
        fail("expected an integer type");
    }

    [[nodiscard]] bool skip(PlyType type) {
        const std::size_t n = ply_type_size(type);
        if (static_cast<std::size_t>(end_ - pos_) < n) {
            return false;
        }
        pos_ += n;
        return true;
    }

    [[noreturn]] void fail(const std::string& what) const { throw InputError(path_, what); }
    [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(end_ - pos_); }

  private:
    template <typename T>
    [[nodiscard]] bool load(T& out) {
        if (static_cast<std::size_t>(end_ - pos_) < sizeof(T)) {
            return false;
        }
        unsigned char bytes[sizeof(T)];
        std::memcpy(bytes, pos_, sizeof(T));
        if (swap_) {
            std::reverse(bytes, bytes + sizeof(T));
        }
        std::memcpy(&out, bytes, sizeof(T));
        pos_ += sizeof(T);
        return true;
    }

    template <typename T>
    [[nodiscard]] bool load_as(std::int64_t& out) {
        T v{};
        if (!load(v)) {
            return false;
        }
        out = static_cast<std::int64_t>(v);
        return true;
    }

    const char* pos_;
    const char* end_;
    bool swap_;
    const std::string& path_;
};

}  // namespace beamtrace::detail
