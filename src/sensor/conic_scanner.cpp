#include "beamtrace/sensor/conic_scanner.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "sensor/detail/mechanism_preset_yaml.hpp"
#include "sensor/detail/scan_pattern_types.hpp"

namespace beamtrace {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

}  // namespace

std::vector<std::string> ConicScannerConfig::validate() const {
    std::vector<std::string> p;
    detail::pulse_timing_problems(pulse_rate_hz, duration_s, start_time_s, p);
    if (!(rotation_rate_hz > 0.0 && std::isfinite(rotation_rate_hz))) {
        p.push_back("rotation_rate_hz must be positive (got " + std::to_string(rotation_rate_hz) +
                    ")");
    } else if (pulse_rate_hz > 0.0 && !(3.0 * rotation_rate_hz <= pulse_rate_hz)) {
        p.push_back("rotation_rate_hz (" + std::to_string(rotation_rate_hz) +
                    ") must leave at least three pulses per revolution (pulse_rate_hz " +
                    std::to_string(pulse_rate_hz) + ")");
    }
    if (!(off_axis_deg > 0.0 && off_axis_deg < 90.0)) {
        p.push_back("off_axis_deg must be in (0, 90) (got " + std::to_string(off_axis_deg) + ")");
    }
    return p;
}

ConicScanner::ConicScanner(ConicScannerConfig config) : config_(std::move(config)) {
    throw_if_problems("conic scanner", config_.validate());
    pulse_count_ = whole_count(config_.duration_s * config_.pulse_rate_hz);
}

double ConicScanner::azimuth_turns(std::uint64_t i) const {
    return detail::frac(static_cast<double>(i) * config_.rotation_rate_hz / config_.pulse_rate_hz);
}

void ConicScanner::generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const {
    const double a = config_.off_axis_deg * kDegToRad;
    const double cos_a = std::cos(a), sin_a = std::sin(a);
    for (std::size_t j = 0; j < count; ++j) {
        const std::uint64_t i = first + j;
        const double turns = azimuth_turns(i);
        const double phi = 2.0 * std::numbers::pi * turns;
        out.time_s[j] = pulse_time_s(i);
        out.direction[j] = {cos_a, sin_a * std::cos(phi), sin_a * std::sin(phi)};
        out.channel[j] = 0;
        out.scan_angle_deg[j] = static_cast<float>(360.0 * (turns < 0.5 ? turns : turns - 1.0));
    }
}

namespace {

std::unique_ptr<ScannerSettings> parse_conic(detail::YamlChecker& c, const YAML::Node& n) {
    ConicScannerConfig s;
    const SensorDataSheet* sheet = detail::parse_mechanism_preset(c, n, conic_presets(), s);
    detail::parse_pulse_timing(c, n, s.pulse_rate_hz, s.duration_s);
    detail::scanner_positive(c, n, "rotation_rate_hz", s.rotation_rate_hz);
    detail::scanner_positive(c, n, "off_axis_deg", s.off_axis_deg);
    detail::scanner_problems(c, n, s.validate());
    auto settings = std::make_unique<SettingsOf<ConicScanner>>(std::move(s));
    settings->set_data_sheet(sheet);
    return settings;
}

constexpr std::array<std::string_view, 5> kConicKeys{"preset", "pulse_rate_hz", "rotation_rate_hz",
                                                     "off_axis_deg", "duration_s"};

}  // namespace

ScanPatternEntry detail::conic_scanner_entry() {
    return {"conic",
            "a conic (Palmer) scanner: the beam at a fixed angle from the axis, turning about it",
            kConicKeys, parse_conic};
}

}  // namespace beamtrace
