// One table of {value, name} per enum: parse, to_string and the choices of a help text come from
// it, so a name is spelled once.
//
//   inline constexpr NameTable<ReturnMode, 2> kReturnModes{
//       "return mode", {{{ReturnMode::first, "first"}, {ReturnMode::last, "last"}}}};
//   kReturnModes.parse("last");     // ReturnMode::last
//   kReturnModes.parse("middle");   // ConfigError "unknown return mode 'middle' (expected first
//                                   //   or last)"
//   kReturnModes.to_string(ReturnMode::first);  // "first"
//   kReturnModes.choices();         // "first | last"
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

template <class Enum>
struct NameEntry {
    Enum value;
    std::string_view name;
};

/// The names in `names` joined as "a, b or c" (the form error messages use).
template <class Range>
[[nodiscard]] std::string join_alternatives(const Range& names) {
    std::string out;
    std::size_t i = 0;
    const std::size_t n = std::size(names);
    for (const auto& name : names) {
        out += i == 0 ? "" : (i + 1 == n ? " or " : ", ");
        out += std::string_view(name);
        ++i;
    }
    return out;
}

template <class Enum, std::size_t N>
class NameTable {
  public:
    /// `what` names the kind in messages ("return mode").
    constexpr NameTable(std::string_view what, std::array<NameEntry<Enum>, N> entries)
        : what_(what), entries_(entries) {}

    /// The value named `name`, or nullopt.
    [[nodiscard]] constexpr std::optional<Enum> find(std::string_view name) const {
        for (const auto& e : entries_) {
            if (e.name == name) {
                return e.value;
            }
        }
        return std::nullopt;
    }

    /// The value named `name`; throws ConfigError "unknown <what> 'name' (expected a, b or c)".
    [[nodiscard]] Enum parse(std::string_view name) const {
        if (const auto v = find(name)) {
            return *v;
        }
        throw ConfigError("unknown " + std::string(what_) + " '" + std::string(name) +
                          "' (expected " + expected() + ")");
    }

    /// The name of `value`; "?" for a value the table lacks.
    [[nodiscard]] constexpr std::string_view to_string(Enum value) const {
        for (const auto& e : entries_) {
            if (e.value == value) {
                return e.name;
            }
        }
        return "?";
    }

    /// "a, b or c".
    [[nodiscard]] std::string expected() const { return join_alternatives(names()); }
    /// "a | b | c", for help texts.
    [[nodiscard]] std::string choices() const {
        std::string out;
        for (const auto& e : entries_) {
            out += (out.empty() ? "" : " | ") + std::string(e.name);
        }
        return out;
    }

    [[nodiscard]] constexpr std::array<std::string_view, N> names() const {
        std::array<std::string_view, N> n{};
        for (std::size_t i = 0; i < N; ++i) {
            n[i] = entries_[i].name;
        }
        return n;
    }
    [[nodiscard]] constexpr const std::array<NameEntry<Enum>, N>& entries() const {
        return entries_;
    }
    [[nodiscard]] constexpr std::string_view what() const { return what_; }

  private:
    std::string_view what_;
    std::array<NameEntry<Enum>, N> entries_;
};

}  // namespace beamtrace
