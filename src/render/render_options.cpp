#include "beamtrace/render/render_options.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// Comma-separated finite numbers; throws ConfigError prefixed with `what`.
std::vector<double> parse_numbers(std::string_view text, const std::string& what) {
    std::vector<double> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        std::string_view item = text.substr(
            start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
        while (!item.empty() && item.front() == ' ') {
            item.remove_prefix(1);
        }
        double x = 0;
        const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), x);
        if (item.empty() || ec != std::errc() || ptr != item.data() + item.size() ||
            !std::isfinite(x)) {
            throw ConfigError(what + ": '" + std::string(item) + "' is not a number");
        }
        out.push_back(x);
        if (comma == std::string_view::npos) {
            break;
        }
        start = comma + 1;
    }
    return out;
}

}  // namespace

Light parse_light(std::string_view text) {
    const std::string what = "--light '" + std::string(text) + "'";
    const std::size_t colon = text.find(':');
    if (colon == std::string_view::npos) {
        throw ConfigError(what + ": expected dir:AZ,EL[,E] or point:X,Y,Z[,P]");
    }
    const std::string_view kind = text.substr(0, colon);
    if (kind != "dir" && kind != "point") {
        throw ConfigError(what + ": unknown light kind '" + std::string(kind) +
                          "' (expected dir or point)");
    }
    const auto v = parse_numbers(text.substr(colon + 1), what);
    if (kind == "dir") {
        if (v.size() < 2 || v.size() > 3) {
            throw ConfigError(what + ": dir takes AZ,EL[,E] (degrees, irradiance)");
        }
        const double e = v.size() == 3 ? v[2] : 1.0;
        if (e < 0.0) {
            throw ConfigError(what + ": irradiance must not be negative");
        }
        return directional_light(v[0] * kDeg, v[1] * kDeg, e);
    }
    if (v.size() < 3 || v.size() > 4) {
        throw ConfigError(what + ": point takes X,Y,Z[,P] (metres, power)");
    }
    const double p = v.size() == 4 ? v[3] : 1.0;
    if (p < 0.0) {
        throw ConfigError(what + ": power must not be negative");
    }
    return point_light({v[0], v[1], v[2]}, p);
}

std::pair<int, int> parse_image_size(std::string_view text) {
    const std::string what = "--size '" + std::string(text) + "'";
    const std::size_t x = text.find('x');
    int w = 0, h = 0;
    const auto num = [&](std::string_view s, int& out) {
        const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
        return !s.empty() && ec == std::errc() && ptr == s.data() + s.size();
    };
    if (x == std::string_view::npos || !num(text.substr(0, x), w) || !num(text.substr(x + 1), h)) {
        throw ConfigError(what + ": expected WIDTHxHEIGHT in pixels, e.g. 640x480");
    }
    if (w < 1 || h < 1 || w > 16384 || h > 16384) {
        throw ConfigError(what + ": width and height must be 1..16384");
    }
    return {w, h};
}

CameraConfig frame_bounds(const Aabb& box, CameraConfig camera) {
    if (box.empty()) {
        throw ConfigError("cannot frame an empty scene: give --camera");
    }
    const Vec3d c(box.center());
    const double r = std::fmax(0.5 * length(Vec3d(box.extent())), 1e-3);
    const double az = 225.0 * kDeg, el = 25.0 * kDeg;
    const Vec3d from{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
    double dist = 3.0 * r;
    if (camera.projection == Projection::pinhole) {
        const double aspect = static_cast<double>(camera.width) / camera.height;
        const double half = std::atan(std::tan(0.5 * camera.vfov_rad) * std::fmin(1.0, aspect));
        dist = 1.1 * r / std::sin(half);
    } else {
        camera.view_width_m =
            2.2 * r * std::fmax(1.0, static_cast<double>(camera.width) / camera.height);
    }
    camera.position_m = c + from * dist;
    camera.orientation = look_at(camera.position_m, c, camera.orientation.roll_rad);
    return camera;
}

}  // namespace beamtrace
