#include "beamtrace/core/camera_pose.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

#include "beamtrace/core/angle_text.hpp"
#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

[[nodiscard]] std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
        s.remove_prefix(1);
    }
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
        s.remove_suffix(1);
    }
    return s;
}

/// The comma-separated fields of `text`, trimmed.
[[nodiscard]] std::vector<std::string_view> split(std::string_view text) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = text.find(',', start);
        out.push_back(trim(text.substr(
            start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
        if (comma == std::string_view::npos) {
            return out;
        }
        start = comma + 1;
    }
}

[[nodiscard]] std::string expected_form(const CameraPoseForm& form) {
    std::string s = form.position_only ? "x,y,z or x,y,z,yaw,pitch" : "x,y,z,yaw,pitch";
    if (form.max_extra > 0) {
        s += " and up to " + std::to_string(form.max_extra) + " more";
    }
    return s;
}

}  // namespace

RollPitchYaw CameraPose::orientation(double roll_rad) const {
    return {roll_rad, pitch_deg * kDeg, yaw_deg * kDeg};
}

Vec3d CameraPose::forward() const {
    const double y = yaw_deg * kDeg, p = pitch_deg * kDeg;
    return {std::cos(p) * std::cos(y), -std::cos(p) * std::sin(y), std::sin(p)};
}

std::optional<ParsedCameraPose> try_parse_camera_pose(std::string_view text,
                                                      const CameraPoseForm& form,
                                                      std::string& why) {
    const auto fields = split(text);
    const std::size_t n = fields.size();
    if (!((n == 3 && form.position_only) || (n >= 5 && n <= 5 + form.max_extra))) {
        why = "expected " + expected_form(form) + " (comma-separated numbers), found " +
              std::to_string(n) + " fields";
        return std::nullopt;
    }
    std::vector<double> v(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::string_view f = fields[i];
        if (i >= 3) {  // yaw, pitch and the extras are angles in degrees: "30", "30deg", "0.5rad"
            const auto a = parse_angle(f, AngleUnit::deg);
            if (!a) {
                why = "field " + std::to_string(i + 1) + " '" + std::string(f) +
                      "' is not an angle (a finite number of degrees, or 0.5rad)";
                return std::nullopt;
            }
            v[i] = a->value;
            continue;
        }
        const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v[i]);
        if (f.empty() || ec != std::errc() || end != f.data() + f.size() || !std::isfinite(v[i])) {
            why = "field " + std::to_string(i + 1) + " '" + std::string(f) +
                  "' is not a finite number";
            return std::nullopt;
        }
    }
    ParsedCameraPose out;
    out.pose.position = {v[0], v[1], v[2]};
    out.has_angles = n >= 5;
    if (out.has_angles) {
        out.pose.yaw_deg = v[3];
        out.pose.pitch_deg = v[4];
        out.extra.assign(v.begin() + 5, v.end());
    }
    return out;
}

ParsedCameraPose parse_camera_pose(std::string_view text, std::string_view what,
                                   const CameraPoseForm& form) {
    std::string why;
    auto pose = try_parse_camera_pose(text, form, why);
    if (!pose) {
        throw ConfigError(std::string(what) + " '" + std::string(text) + "': " + why);
    }
    return *std::move(pose);
}

}  // namespace beamtrace
