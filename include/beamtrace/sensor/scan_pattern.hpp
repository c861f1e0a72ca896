// Scan patterns: where a sensor fires its pulses, and when, in the sensor frame.
//
// Sensor frame (the report's): x forward (optical axis), y left, z up. A pattern yields pulse i's
// emission time, unit direction, channel (beam/row) and scan angle; nothing of pulse i depends on
// any other pulse, so any chunking or threading of generate() gives bit-identical results. The
// platform's pose at each pulse time (see trajectory.hpp) carries the directions into the world.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// sin and cos of angles a pattern met before, kept from batch to batch by whoever reuses the
/// PulseBatch: a direct-mapped table keyed by the angle's exact bits, so what it gives is what
/// std::cos and std::sin give. A line scanner's lines repeat their angles bit for bit (within a
/// binade of the line count), so most of its pulses skip the sincos.
struct SincosMemo {
    /// Every entry holds an angle and its cos and sin: at first 0, 1, 0.
    struct Entry {
        std::uint64_t angle_bits = 0;
        double cos = 1.0, sin = 0.0;
    };
    std::vector<Entry> entries;  ///< empty until a pattern sizes it
};

/// A batch of pulses, structure of arrays (every array has size()).
struct PulseBatch {
    std::vector<double> time_s;          ///< emission time (ScanPattern::pulse_time_s)
    std::vector<Vec3d> direction;        ///< unit length, sensor frame
    std::vector<std::uint16_t> channel;  ///< beam / laser / image row that fired the pulse
    /// Horizontal angle of the beam from the sensor's x axis, positive towards +y (left), in
    /// degrees. What it means per pattern (azimuth, mirror angle, image column) is documented
    /// with each pattern. NOTE: LAS counts its scan angle negative to the LEFT of the flight
    /// direction (positive to the right), and LAS 1.4 measures it from the data's vertical (roll
    /// included); a LAS writer for a nadir line scanner negates this value (and adds the roll
    /// for the 1.4 meaning).
    std::vector<float> scan_angle_deg;
    /// The index of the scanner that fired the pulse when several scanners share a platform
    /// (ScannerSet, sensor/scanner_set.hpp); 0 for every other pattern.
    std::vector<std::uint8_t> scanner;
    /// A pattern's scratch, kept across batches (never part of the pulses; resize leaves it).
    SincosMemo sincos_memo;

    [[nodiscard]] std::size_t size() const { return time_s.size(); }
    [[nodiscard]] bool empty() const { return time_s.empty(); }
    void resize(std::size_t n) {
        time_s.resize(n);
        direction.resize(n);
        channel.resize(n);
        scan_angle_deg.resize(n);
        scanner.resize(n);
    }
    void clear() { resize(0); }
};

/// The image a pattern's pulses form: pulse u * height + v is pixel row v, column u (the
/// report's ray order, image_sensor.hpp).
struct ImageGrid {
    int width = 0;
    int height = 0;
    friend bool operator==(const ImageGrid&, const ImageGrid&) = default;
};

/// The pulses of a whole survey, in firing order.
class ScanPattern {
  public:
    virtual ~ScanPattern() = default;
    ScanPattern() = default;
    ScanPattern(const ScanPattern&) = default;
    ScanPattern& operator=(const ScanPattern&) = default;
    ScanPattern(ScanPattern&&) = default;
    ScanPattern& operator=(ScanPattern&&) = default;

    /// Total pulses of the survey.
    [[nodiscard]] virtual std::uint64_t pulse_count() const = 0;
    /// Pulses per second (all channels together); for a non-uniform pattern (LegSequence) the
    /// mean rate over [start_time_s(), end_time_s()].
    [[nodiscard]] virtual double pulse_rate_hz() const = 0;
    /// Emission time of pulse 0 (GPS time or any other time base shared with the trajectory).
    [[nodiscard]] virtual double start_time_s() const = 0;

    /// Emission time of pulse i. Uniform patterns (every type of the registry): start_time_s()
    /// + i / pulse_rate_hz(). A pattern whose times are not uniform (LegSequence: legs with
    /// their own rates and gaps) overrides it; the times of generate() always agree with it.
    /// Users take times from generate()'s PulseBatch::time_s, never from start + i / rate.
    [[nodiscard]] virtual double pulse_time_s(std::uint64_t i) const {
        return uniform_time_s(start_time_s(), pulse_rate_hz(), i);
    }
    /// Pulse i's time in a uniform pattern: start_s + i / rate_hz (what pulse_time_s gives,
    /// for a generate() that keeps the two in locals).
    [[nodiscard]] static double uniform_time_s(double start_s, double rate_hz, std::uint64_t i) {
        return start_s + static_cast<double>(i) / rate_hz;
    }
    /// The end of the survey: the time the last pulse's slot ends (uniform patterns:
    /// start_time_s() + pulse_count() / pulse_rate_hz(), i.e. pulse_time_s(pulse_count())).
    [[nodiscard]] virtual double end_time_s() const { return pulse_time_s(pulse_count()); }

    /// The image grid of the pulses when they form one image (an image pattern firing a single
    /// frame): the survey then writes range and label images. nullopt for every other pattern.
    [[nodiscard]] virtual std::optional<ImageGrid> image_grid() const { return std::nullopt; }

    /// Fills `out` (resized to `count`) with pulses [first, first + count). Throws
    /// std::out_of_range when that goes past pulse_count().
    void generate(std::uint64_t first, std::size_t count, PulseBatch& out) const;

  private:
    /// Writes pulses [first, first + count) into out[0, count); `out` already has `count` slots
    /// and the range is within pulse_count().
    virtual void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const = 0;
};

/// Throws ConfigError "<subject>: problem; problem; ..." when `problems` is not empty.
void throw_if_problems(std::string_view subject, const std::vector<std::string>& problems);

/// The whole number of events in `x` (a duration times a rate), forgiving a relative rounding
/// error of 1e-9 (so 0.1 s at 1000 Hz is 100, not 99); 0 for x < 0 or NaN.
[[nodiscard]] std::uint64_t whole_count(double x);

}  // namespace beamtrace
