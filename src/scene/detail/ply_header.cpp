#include "scene/detail/ply_header.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <utility>

#include "beamtrace/core/error.hpp"
#include "text/text_scan.hpp"

namespace beamtrace::detail {
namespace {

[[nodiscard]] std::optional<PlyType> parse_type(std::string_view name) {
    static constexpr std::array<std::pair<std::string_view, PlyType>, 16> kTypes{{
        {"char", PlyType::int8},
        {"int8", PlyType::int8},
        {"uchar", PlyType::uint8},
        {"uint8", PlyType::uint8},
        {"short", PlyType::int16},
        {"int16", PlyType::int16},
        {"ushort", PlyType::uint16},
        {"uint16", PlyType::uint16},
        {"int", PlyType::int32},
        {"int32", PlyType::int32},
        {"uint", PlyType::uint32},
        {"uint32", PlyType::uint32},
        {"float", PlyType::float32},
        {"float32", PlyType::float32},
        {"double", PlyType::float64},
        {"float64", PlyType::float64},
    }};
    for (const auto& [type_name, type] : kTypes) {
        if (type_name == name) {
            return type;
        }
    }
    return std::nullopt;
}

/// Splits a header line into blank-separated words.
[[nodiscard]] std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t pos = 0;
    while (pos < line.size()) {
        while (pos < line.size() && is_blank(line[pos])) {
            ++pos;
        }
        const std::size_t start = pos;
        while (pos < line.size() && !is_blank(line[pos])) {
            ++pos;
        }
        if (pos > start) {
            words.push_back(line.substr(start, pos - start));
        }
    }
    return words;
}

class HeaderParser {
  public:
    HeaderParser(std::string_view bytes, const std::string& path) : bytes_(bytes), path_(path) {}

    PlyHeader parse() {
        if (!next_line() || split_words(line_) != std::vector<std::string_view>{"ply"}) {
            throw InputError(path_, 1, "not a PLY file (the first line must be 'ply')");
        }
        bool have_format = false;
        while (next_line()) {
            const auto words = split_words(line_);
            if (words.empty()) {
                continue;
            }
            const std::string_view keyword = words[0];
            if (keyword == "format") {
                parse_format(words);
                have_format = true;
            } else if (keyword == "element") {
                parse_element(words);
            } else if (keyword == "property") {
                parse_property(words);
            } else if (keyword == "end_header") {
                if (!have_format) {
                    throw InputError(path_, line_no_, "header has no 'format' line");
                }
                header_.data_offset = pos_;
                header_.data_line = line_no_ + 1;
                return std::move(header_);
            }
            // comment, obj_info and unknown lines (some exporters write free text) are ignored.
        }
        throw InputError(path_, line_no_, "header has no 'end_header' line");
    }

  private:
    bool next_line() {
        if (pos_ >= bytes_.size()) {
            return false;
        }
        const std::size_t nl = bytes_.find('\n', pos_);
        const std::size_t end = nl == std::string_view::npos ? bytes_.size() : nl;
        line_ = bytes_.substr(pos_, end - pos_);
        pos_ = end == bytes_.size() ? end : end + 1;
        ++line_no_;
        return true;
    }

    void parse_format(const std::vector<std::string_view>& words) {
        const std::string_view name = words.size() > 1 ? words[1] : std::string_view{};
        if (name == "ascii") {
            header_.format = PlyFormat::ascii;
        } else if (name == "binary_little_endian") {
            header_.format = PlyFormat::binary_little_endian;
        } else if (name == "binary_big_endian") {
            header_.format = PlyFormat::binary_big_endian;
        } else {
            throw InputError(path_, line_no_, "unknown PLY format '" + std::string(name) + "'");
        }
    }

    void parse_element(const std::vector<std::string_view>& words) {
        PlyElement element;
        if (words.size() != 3 || !parse_number(words[2], element.count)) {
            throw InputError(path_, line_no_, "expected 'element <name> <count>'");
        }
        element.name = std::string(words[1]);
        header_.elements.push_back(std::move(element));
    }

    void parse_property(const std::vector<std::string_view>& words) {
        if (header_.elements.empty()) {
            throw InputError(path_, line_no_, "property declared before any element");
        }
        PlyProperty property;
        if (words.size() == 5 && words[1] == "list") {
            property.is_list = true;
            property.count_type = type_or_throw(words[2]);
            property.type = type_or_throw(words[3]);
            property.name = std::string(words[4]);
            if (!ply_type_is_integer(property.count_type)) {
                throw InputError(path_, line_no_, "list count type must be an integer type");
            }
        } else if (words.size() == 3 && words[1] != "list") {
            property.type = type_or_throw(words[1]);
            property.name = std::string(words[2]);
        } else {
            throw InputError(path_, line_no_,
                             "expected 'property <type> <name>' or "
                             "'property list <count type> <item type> <name>'");
        }
        header_.elements.back().properties.push_back(std::move(property));
    }

    [[nodiscard]] PlyType type_or_throw(std::string_view name) const {
        if (const auto type = parse_type(name)) {
            return *type;
        }
        throw InputError(path_, line_no_, "unknown property type '" + std::string(name) + "'");
    }

    std::string_view bytes_;
    const std::string& path_;
    std::size_t pos_ = 0;
    long line_no_ = 0;
    std::string_view line_;
    PlyHeader header_;
};

}  // namespace

std::size_t ply_type_size(PlyType type) {
    switch (type) {
        case PlyType::int8:
        case PlyType::uint8:
            return 1;
        case PlyType::int16:
        case PlyType::uint16:
            return 2;
        case PlyType::int32:
        case PlyType::uint32:
        case PlyType::float32:
            return 4;
        case PlyType::float64:
            return 8;
    }
    return 0;
}

bool ply_type_is_integer(PlyType type) {
    return type != PlyType::float32 && type != PlyType::float64;
}

std::size_t PlyElement::find(std::string_view property_name) const {
    for (std::size_t i = 0; i < properties.size(); ++i) {
        if (properties[i].name == property_name) {
            return i;
        }
    }
    return npos;
}

std::size_t PlyElement::min_instance_bytes(PlyFormat format) const {
    if (format == PlyFormat::ascii) {
        // Each value takes at least one character and a separator.
        return std::max<std::size_t>(1, 2 * properties.size());
    }
    std::size_t bytes = 0;
    for (const auto& p : properties) {
        bytes += ply_type_size(p.is_list ? p.count_type : p.type);
    }
    return std::max<std::size_t>(1, bytes);
}

const PlyElement* PlyHeader::find(std::string_view element_name) const {
    const auto it = std::find_if(elements.begin(), elements.end(),
                                 [&](const PlyElement& e) { return e.name == element_name; });
    return it == elements.end() ? nullptr : &*it;
}

PlyHeader parse_ply_header(std::string_view bytes, const std::string& path) {
    return HeaderParser(bytes, path).parse();
}

}  // namespace beamtrace::detail
