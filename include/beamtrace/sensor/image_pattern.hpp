// The report's image sensors (`castRaysPinhole`, `castRaysScan`, image_sensor.hpp) as timed
// scan patterns.
//
// Conventions:
// - Pulses come in the report's ray order, ray index = u * height + v (u the column, 0 = left;
//   v the row, 0 = top), repeated for `frames` images: pulse i is pixel i % (width * height) of
//   frame i / (width * height). t_i = start_time_s + i / pulse_rate_hz.
// - Directions are exactly (bit for bit) those of cast_rays_pinhole / cast_rays_scan for the
//   same ImageSensorConfig, INCLUDING its `orientation` (which thus acts as a fixed boresight
//   in front of any mount). Its `position_m` is ignored: where the sensor is comes from the
//   trajectory and mount, so a StaticPlatform at position_m with an identity mount reproduces
//   the report's rays.
// - channel = the row v; scan_angle_deg = the column's horizontal angle from the optical axis
//   before the orientation, positive to the left (+y): the azimuth phi_u for "scan" and
//   atan(y_u) for "pinhole".
// - The report's push-broom (Appendix B.1) is a pinhole of width 1 with `frames` lines on a
//   moving trajectory.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/core/mat3.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

/// The two projections, which are the scan pattern registry's "pinhole" and "scan" types.
enum class ImageProjection { pinhole, scan };

/// The most pixels (width x height) of a pattern firing one frame, whose range and label images
/// a survey holds whole: 2^26 = 67108864, e.g. 8192 x 8192 (about 1 GiB with the images).
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 26;

struct ImagePatternConfig {
    ImageSensorConfig image;  ///< size, fields of view, orientation
    ImageProjection projection = ImageProjection::pinhole;
    double pulse_rate_hz = 1.0e6;  ///< pixels per second
    std::uint64_t frames = 1;      ///< images fired one after the other
    double start_time_s = 0.0;     ///< time of pulse 0

    /// Every problem with these settings (the image's included); empty when valid. Heights
    /// above 65536 rows are refused (the row is the 16-bit channel), and one frame of more than
    /// kMaxImagePixels pixels (its images would not fit in memory).
    [[nodiscard]] std::vector<std::string> validate() const;
};

class ImagePattern final : public ScanPattern {
  public:
    using Config = ImagePatternConfig;

    /// Throws ConfigError listing every problem of `config`.
    explicit ImagePattern(ImagePatternConfig config);

    [[nodiscard]] std::uint64_t pulse_count() const override { return pulse_count_; }
    [[nodiscard]] double pulse_rate_hz() const override { return config_.pulse_rate_hz; }
    [[nodiscard]] double start_time_s() const override { return config_.start_time_s; }
    [[nodiscard]] const ImagePatternConfig& config() const { return config_; }
    [[nodiscard]] std::uint64_t pixels_per_frame() const { return pixels_; }
    /// width x height when the pattern fires a single frame.
    [[nodiscard]] std::optional<ImageGrid> image_grid() const override;

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;

    ImagePatternConfig config_;
    std::uint64_t pixels_ = 0;
    std::uint64_t pulse_count_ = 0;
    Mat3 orientation_;
    std::vector<double> column_value_;  ///< y_u (pinhole) or phi_u (scan)
    std::vector<double> row_value_;     ///< z_v (pinhole) or theta_v (scan)
    /// scan: cos and sin of phi_u and theta_v, worked out once (the same values per pulse).
    std::vector<double> column_cos_, column_sin_, row_cos_, row_sin_;
    std::vector<float> column_angle_deg_;
};

}  // namespace beamtrace
