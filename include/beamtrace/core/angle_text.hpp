// Angles written with or without a unit: "60", "60deg", "1.05rad" (docs/units.md). A key or an
// option has a unit (the `_deg` or `_rad` of its name); an explicit unit on the value converts
// to it, and a plain number in a degree key that looks like a multiple of pi/12 in radians
// (1.5708, 3.14) is taken for a unit mistake unless written with "deg".
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

enum class AngleUnit { deg, rad };

/// An angle as written and its value in the key's unit.
struct AngleText {
    double value = 0.0;          ///< in the unit asked for
    bool explicit_unit = false;  ///< the text named a unit ("deg", "rad", "°")
};

/// Parses a finite number with an optional unit suffix ("deg", "°", "rad", spaces allowed
/// before it) into `unit`; nullopt for anything else.
[[nodiscard]] std::optional<AngleText> parse_angle(std::string_view text, AngleUnit unit);

/// For a plain number given in degrees: "-π/2" when it lies within 0.002 of a multiple k·π/12
/// with 2 <= |k| <= 24 (π/6 to 2π), i.e. it reads as radians typed into degrees; else nullopt.
[[nodiscard]] std::optional<std::string> radian_lookalike(double degrees);

/// The one-line complaint for a radian-looking `value` of `key` (in degrees), naming the
/// multiple of π, the degrees it would be, and how to keep the value.
[[nodiscard]] std::string radian_lookalike_message(double value, const std::string& multiple);

/// An angle option's text ("0.5", "30deg") in `unit`; throws ConfigError "<what> expects an
/// angle ..., got '<text>'" otherwise.
[[nodiscard]] double parse_angle_option(std::string_view text, std::string_view what,
                                        AngleUnit unit);

/// "a,b,c": three angles, each with an optional unit, in `unit`; ConfigError otherwise.
[[nodiscard]] Vec3d parse_angle_vec3(std::string_view text, std::string_view what, AngleUnit unit);

/// For an option in radians: the warning that `value` (given without a unit) lies beyond
/// ±2π, so is likely degrees; empty when it does not.
[[nodiscard]] std::string radians_beyond_turn_warning(double value, std::string_view what);

}  // namespace beamtrace
