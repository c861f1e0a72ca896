#include "beamtrace/sensor/fibre_scanner.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "sensor/detail/scan_pattern_types.hpp"

namespace beamtrace {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr int kMaxFibres = 65536;  // channel is 16 bits

}  // namespace

std::vector<std::string> FibreScannerConfig::validate() const {
    std::vector<std::string> p;
    detail::pulse_timing_problems(pulse_rate_hz, duration_s, start_time_s, p);
    if (!(fibres >= 2 && fibres <= kMaxFibres)) {
        p.push_back("fibres must be in [2, 65536] (got " + std::to_string(fibres) + ")");
    }
    if (!(fan_deg > 0.0 && fan_deg < 180.0)) {
        p.push_back("fan_deg must be in (0, 180) (got " + std::to_string(fan_deg) + ")");
    }
    return p;
}

FibreScanner::FibreScanner(FibreScannerConfig config) : config_(std::move(config)) {
    throw_if_problems("fibre scanner", config_.validate());
    pulse_count_ = whole_count(config_.duration_s * config_.pulse_rate_hz);
}

double FibreScanner::fibre_angle_deg(int k) const {
    const double fan = config_.fan_deg;
    return -0.5 * fan + static_cast<double>(k) * fan / static_cast<double>(config_.fibres - 1);
}

void FibreScanner::generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const {
    const auto fibres = static_cast<std::uint64_t>(config_.fibres);
    for (std::size_t j = 0; j < count; ++j) {
        const std::uint64_t i = first + j;
        const auto k = static_cast<int>(i % fibres);
        const double a_deg = fibre_angle_deg(k);
        const double a = a_deg * kDegToRad;
        out.time_s[j] = pulse_time_s(i);
        out.direction[j] = {std::cos(a), std::sin(a), 0.0};
        out.channel[j] = static_cast<std::uint16_t>(k);
        out.scan_angle_deg[j] = static_cast<float>(a_deg);
    }
}

namespace {

std::unique_ptr<ScannerSettings> parse_fibre(detail::YamlChecker& c, const YAML::Node& n) {
    FibreScannerConfig s;
    detail::parse_pulse_timing(c, n, s.pulse_rate_hz, s.duration_s);
    long fibres = 0;
    if (n["fibres"] && c.integer(n["fibres"], "scanner.fibres", 2, kMaxFibres, fibres)) {
        s.fibres = static_cast<int>(fibres);
    }
    detail::scanner_positive(c, n, "fan_deg", s.fan_deg);
    detail::scanner_problems(c, n, s.validate());
    return std::make_unique<SettingsOf<FibreScanner>>(std::move(s));
}

constexpr std::array<std::string_view, 4> kFibreKeys{"pulse_rate_hz", "fibres", "fan_deg",
                                                     "duration_s"};

}  // namespace

ScanPatternEntry detail::fibre_scanner_entry() {
    return {"fibre", "a fibre-array line scanner: n fixed beams across track, fired in turn",
            kFibreKeys, parse_fibre};
}

}  // namespace beamtrace
