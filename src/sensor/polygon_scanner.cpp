#include "beamtrace/sensor/polygon_scanner.hpp"

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

std::vector<std::string> PolygonScannerConfig::validate() const {
    std::vector<std::string> p;
    detail::pulse_timing_problems(pulse_rate_hz, duration_s, start_time_s, p);
    const bool facets_ok = facets >= 2 && facets <= 360;
    if (!facets_ok) {
        p.push_back("facets must be in [2, 360] (got " + std::to_string(facets) + ")");
    }
    if (!(rotation_rate_hz > 0.0 && std::isfinite(rotation_rate_hz))) {
        p.push_back("rotation_rate_hz must be positive (got " + std::to_string(rotation_rate_hz) +
                    ")");
    } else if (facets_ok && pulse_rate_hz > 0.0 &&
               !(2.0 * facets * rotation_rate_hz <= pulse_rate_hz)) {
        p.push_back("facets x rotation_rate_hz (" + std::to_string(facets * rotation_rate_hz) +
                    " lines/s) must leave at least two pulses per line (pulse_rate_hz " +
                    std::to_string(pulse_rate_hz) + ")");
    }
    if (!(usable_fraction > 0.0 && usable_fraction <= 1.0)) {
        p.push_back("usable_fraction must be in (0, 1] (got " + std::to_string(usable_fraction) +
                    ")");
    } else if (facets == 2 && usable_fraction == 1.0) {
        p.push_back("a 2-facet mirror needs usable_fraction below 1 (a scan angle below 180 deg)");
    }
    return p;
}

PolygonScanner::PolygonScanner(PolygonScannerConfig config) : config_(std::move(config)) {
    throw_if_problems("polygon scanner", config_.validate());
    pulse_count_ = whole_count(config_.duration_s * config_.pulse_rate_hz);
}

double PolygonScanner::line_rate_hz() const {
    return static_cast<double>(config_.facets) * config_.rotation_rate_hz;
}

double PolygonScanner::scan_angle_max_deg() const {
    return 360.0 / static_cast<double>(config_.facets) * config_.usable_fraction;
}

std::uint64_t PolygonScanner::line_of_pulse(std::uint64_t i) const {
    return static_cast<std::uint64_t>(
        std::floor(static_cast<double>(i) * line_rate_hz() / config_.pulse_rate_hz));
}

void PolygonScanner::generate_pulses(std::uint64_t first, std::size_t count,
                                     PulseBatch& out) const {
    const double a = scan_angle_max_deg(), rate = line_rate_hz();
    const auto facets = static_cast<std::uint64_t>(config_.facets);
    for (std::size_t j = 0; j < count; ++j) {
        const std::uint64_t i = first + j;
        // The same expression as line_of_pulse, so a pulse's angle and line always agree.
        const double lines = static_cast<double>(i) * rate / config_.pulse_rate_hz;
        const double s_deg = -a + 2.0 * a * detail::frac(lines);
        const double s = s_deg * kDegToRad;
        out.time_s[j] = pulse_time_s(i);
        out.direction[j] = {std::cos(s), std::sin(s), 0.0};
        out.channel[j] =
            static_cast<std::uint16_t>(static_cast<std::uint64_t>(std::floor(lines)) % facets);
        out.scan_angle_deg[j] = static_cast<float>(s_deg);
    }
}

namespace {

std::unique_ptr<ScannerSettings> parse_polygon(detail::YamlChecker& c, const YAML::Node& n) {
    PolygonScannerConfig s;
    const SensorDataSheet* sheet = detail::parse_mechanism_preset(c, n, polygon_presets(), s);
    detail::parse_pulse_timing(c, n, s.pulse_rate_hz, s.duration_s);
    long facets = 0;
    if (n["facets"] && c.integer(n["facets"], "scanner.facets", 2, 360, facets)) {
        s.facets = static_cast<int>(facets);
    }
    detail::scanner_positive(c, n, "rotation_rate_hz", s.rotation_rate_hz);
    detail::scanner_positive(c, n, "usable_fraction", s.usable_fraction);
    detail::scanner_problems(c, n, s.validate());
    auto settings = std::make_unique<SettingsOf<PolygonScanner>>(std::move(s));
    settings->set_data_sheet(sheet);
    return settings;
}

constexpr std::array<std::string_view, 6> kPolygonKeys{
    "preset", "pulse_rate_hz", "facets", "rotation_rate_hz", "usable_fraction", "duration_s"};

}  // namespace

ScanPatternEntry detail::polygon_scanner_entry() {
    return {"polygon", "a rotating polygon mirror: a sawtooth, one line per facet", kPolygonKeys,
            parse_polygon};
}

}  // namespace beamtrace
