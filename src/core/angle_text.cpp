#include "beamtrace/core/angle_text.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && s.front() == ' ') {
        s.remove_prefix(1);
    }
    while (!s.empty() && s.back() == ' ') {
        s.remove_suffix(1);
    }
    return s;
}

/// Removes `suffix` from the end of `s` when it is there.
bool strip(std::string_view& s, std::string_view suffix) {
    if (s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix) {
        s.remove_suffix(suffix.size());
        return true;
    }
    return false;
}

/// The shortest text of x that reads back as x.
std::string shortest(double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return {buf, r.ptr};
}

}  // namespace

std::optional<AngleText> parse_angle(std::string_view text, AngleUnit unit) {
    std::string_view s = trim(text);
    std::optional<AngleUnit> given;
    if (strip(s, "deg") || strip(s, "\xC2\xB0")) {  // "°" in UTF-8
        given = AngleUnit::deg;
    } else if (strip(s, "rad")) {
        given = AngleUnit::rad;
    }
    s = trim(s);
    if (!s.empty() && s.front() == '+') {
        s.remove_prefix(1);
    }
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) {
        return std::nullopt;
    }
    constexpr double kDeg = 180.0 / std::numbers::pi;
    if (given && *given != unit) {
        v = unit == AngleUnit::deg ? v * kDeg : v / kDeg;
    }
    return AngleText{v, given.has_value()};
}

std::optional<std::string> radian_lookalike(double degrees) {
    const double k = std::round(degrees / (std::numbers::pi / 12.0));
    const double a = std::abs(k);
    if (a < 2 || a > 24 || std::abs(degrees - k * std::numbers::pi / 12.0) > 0.002) {
        return std::nullopt;
    }
    // k/12 in lowest terms: n·π/d.
    long n = static_cast<long>(a), d = 12;
    for (const long p : {2L, 3L}) {
        while (n % p == 0 && d % p == 0) {
            n /= p;
            d /= p;
        }
    }
    std::string text = degrees < 0 ? "-" : "";
    text += (n == 1 ? "" : std::to_string(n)) + "\xCF\x80";  // "π"
    if (d != 1) {
        text += "/" + std::to_string(d);
    }
    return text;
}

std::string radian_lookalike_message(double value, const std::string& multiple) {
    // The degrees of the multiple of pi/12 it resembles: 15 degrees each.
    const double deg = 15.0 * std::round(value / (std::numbers::pi / 12.0));
    return shortest(value) + " looks like " + multiple + " in radians, but this value is in " +
           "degrees: write " + shortest(deg) + " (degrees), " + shortest(value) +
           "rad (radians), or " + shortest(value) + "deg to keep it as degrees";
}

double parse_angle_option(std::string_view text, std::string_view what, AngleUnit unit) {
    const auto a = parse_angle(text, unit);
    if (!a) {
        throw ConfigError(std::string(what) + " expects an angle in " +
                          (unit == AngleUnit::deg ? "degrees" : "radians") +
                          " (a number, or with its unit: 60deg, 1.05rad), got '" +
                          std::string(text) + "'");
    }
    return a->value;
}

Vec3d parse_angle_vec3(std::string_view text, std::string_view what, AngleUnit unit) {
    Vec3d v;
    std::string_view rest = text;
    for (int k = 0; k < 3; ++k) {
        const std::size_t comma = rest.find(',');
        const auto a = (k < 2) == (comma != std::string_view::npos)
                           ? parse_angle(rest.substr(0, comma), unit)
                           : std::nullopt;
        if (!a) {
            throw ConfigError(std::string(what) + " expects three comma-separated angles in " +
                              (unit == AngleUnit::deg ? "degrees" : "radians") +
                              " (each may carry its unit: 0,-90deg,0), got '" + std::string(text) +
                              "'");
        }
        v[k] = a->value;
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    }
    return v;
}

std::string radians_beyond_turn_warning(double value, std::string_view what) {
    if (std::abs(value) <= 2.0 * std::numbers::pi + 1e-9) {
        return {};
    }
    return std::string(what) + ": " + shortest(value) + " rad is more than a full turn (2" +
           "\xCF\x80); this option is in radians: write " + shortest(value) +
           "deg if you meant degrees";
}

}  // namespace beamtrace
