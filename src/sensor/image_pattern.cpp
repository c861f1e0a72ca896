#include "beamtrace/sensor/image_pattern.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "sensor/detail/scan_pattern_types.hpp"
#include "sensor/detail/scanner_yaml.hpp"

namespace beamtrace {

std::vector<std::string> ImagePatternConfig::validate() const {
    const bool scanning = projection == ImageProjection::scan;
    std::vector<std::string> p = image.validate(scanning);
    if (projection != ImageProjection::pinhole && projection != ImageProjection::scan) {
        p.push_back("projection must be pinhole or scan");
    }
    if (image.height > 65536) {
        p.push_back("height must be at most 65536 rows (got " + std::to_string(image.height) + ")");
    }
    if (!(pulse_rate_hz > 0.0 && std::isfinite(pulse_rate_hz))) {
        p.push_back("pulse_rate_hz must be positive (got " + std::to_string(pulse_rate_hz) + ")");
    }
    if (frames < 1) {
        p.push_back("frames must be at least 1");
    } else if (image.width >= 1 && image.height >= 1 &&
               static_cast<double>(frames) * static_cast<double>(image.width) *
                       static_cast<double>(image.height) >
                   9.0e15) {
        p.push_back("frames x width x height must be below 9e15 pulses");
    } else if (frames == 1 && image.width >= 1 && image.height >= 1 &&
               std::uint64_t(image.width) * std::uint64_t(image.height) > kMaxImagePixels) {
        p.push_back("width x height of one frame (" + std::to_string(image.width) + " x " +
                    std::to_string(image.height) + ") must be at most " +
                    std::to_string(kMaxImagePixels) +
                    " pixels, the limit of the range and label images");
    }
    if (!std::isfinite(start_time_s)) {
        p.push_back("start_time_s must be finite");
    }
    return p;
}

ImagePattern::ImagePattern(ImagePatternConfig config) : config_(std::move(config)) {
    throw_if_problems("image pattern", config_.validate());
    const ImageSensorConfig& c = config_.image;
    pixels_ = static_cast<std::uint64_t>(c.width) * static_cast<std::uint64_t>(c.height);
    pulse_count_ = pixels_ * config_.frames;
    orientation_ = rpy_matrix(c.orientation);
    // The same expressions as cast_rays_pinhole / cast_rays_scan (image_sensor.cpp), so the
    // directions agree bit for bit.
    const bool scan = config_.projection == ImageProjection::scan;
    const double y0 = scan ? 0.5 * c.hfov_rad : std::tan(0.5 * c.hfov_rad);
    const double z0 = scan ? 0.5 * c.vfov_rad : std::tan(0.5 * c.vfov_rad);
    column_value_.resize(static_cast<std::size_t>(c.width));
    column_angle_deg_.resize(column_value_.size());
    for (int u = 0; u < c.width; ++u) {
        const double value = linspace_at(y0, -y0, c.width, u);
        const double angle = scan ? value : std::atan(value);
        column_value_[static_cast<std::size_t>(u)] = value;
        column_angle_deg_[static_cast<std::size_t>(u)] =
            static_cast<float>(angle * 180.0 / std::numbers::pi);
    }
    row_value_.resize(static_cast<std::size_t>(c.height));
    for (int v = 0; v < c.height; ++v) {
        row_value_[static_cast<std::size_t>(v)] = linspace_at(z0, -z0, c.height, v);
    }
    if (scan) {
        for (const double phi : column_value_) {
            column_cos_.push_back(std::cos(phi));
            column_sin_.push_back(std::sin(phi));
        }
        for (const double theta : row_value_) {
            row_cos_.push_back(std::cos(theta));
            row_sin_.push_back(std::sin(theta));
        }
    }
}

void ImagePattern::generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const {
    const auto height = static_cast<std::uint64_t>(config_.image.height);
    const bool scan = config_.projection == ImageProjection::scan;
    for (std::size_t j = 0; j < count; ++j) {
        const std::uint64_t i = first + j;
        const std::uint64_t pixel = i % pixels_;
        const auto u = static_cast<std::size_t>(pixel / height);
        const auto v = static_cast<std::size_t>(pixel % height);
        Vec3d d;
        if (scan) {
            d = {row_cos_[v] * column_cos_[u], row_cos_[v] * column_sin_[u], row_sin_[v]};
        } else {
            d = normalize(Vec3d{1.0, column_value_[u], row_value_[v]});
        }
        out.time_s[j] = pulse_time_s(i);
        out.direction[j] = sensor_to_world(d, orientation_);
        out.channel[j] = static_cast<std::uint16_t>(v);
        out.scan_angle_deg[j] = column_angle_deg_[u];
    }
}

std::optional<ImageGrid> ImagePattern::image_grid() const {
    if (config_.frames != 1) {
        return std::nullopt;
    }
    return ImageGrid{config_.image.width, config_.image.height};
}

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// The keys of both projections (pinhole and scan share them).
std::unique_ptr<ScannerSettings> parse_image(detail::YamlChecker& c, const YAML::Node& n,
                                             ImageProjection projection) {
    ImagePatternConfig s;
    s.projection = projection;
    long v = 0;
    if (n["width"] && c.integer(n["width"], "scanner.width", 1, 1 << 20, v)) {
        s.image.width = static_cast<int>(v);
    }
    if (n["height"] && c.integer(n["height"], "scanner.height", 1, 1 << 16, v)) {
        s.image.height = static_cast<int>(v);
    }
    if (n["frames"] && c.integer(n["frames"], "scanner.frames", 1, 1L << 30, v)) {
        s.frames = static_cast<std::uint64_t>(v);
    }
    double deg = 0;
    if (n["hfov_deg"] && c.number(n["hfov_deg"], "scanner.hfov_deg", deg)) {
        s.image.hfov_rad = deg * kDeg;
    }
    if (n["vfov_deg"] && c.number(n["vfov_deg"], "scanner.vfov_deg", deg)) {
        s.image.vfov_rad = deg * kDeg;
    }
    detail::scanner_positive(c, n, "pulse_rate_hz", s.pulse_rate_hz);
    detail::scanner_problems(c, n, s.validate());
    return std::make_unique<SettingsOf<ImagePattern>>(std::move(s));
}

constexpr std::array<std::string_view, 6> kImageKeys{"width",    "height", "hfov_deg",
                                                     "vfov_deg", "frames", "pulse_rate_hz"};

StaticRays image_rays(const StaticScanInput& in, bool scanning) {
    return {scanning ? cast_rays_scan(in.sensor) : cast_rays_pinhole(in.sensor),
            ImageGrid{in.sensor.width, in.sensor.height}};
}

}  // namespace

ScanPatternEntry detail::pinhole_pattern_entry() {
    return {"pinhole",
            "an image sensor: rays through a flat image plane (the report's castRaysPinhole)",
            kImageKeys,
            [](detail::YamlChecker& c, const YAML::Node& n) {
                return parse_image(c, n, ImageProjection::pinhole);
            },
            [](const StaticScanInput& in) { return image_rays(in, false); },
            [](const StaticScanInput& in) { return in.sensor.validate(false); }};
}

ScanPatternEntry detail::scan_pattern_entry() {
    return {"scan",
            "an image sensor: rows and columns evenly spaced in angle (the report's castRaysScan)",
            kImageKeys,
            [](detail::YamlChecker& c, const YAML::Node& n) {
                return parse_image(c, n, ImageProjection::scan);
            },
            [](const StaticScanInput& in) { return image_rays(in, true); },
            [](const StaticScanInput& in) { return in.sensor.validate(true); }};
}

}  // namespace beamtrace
