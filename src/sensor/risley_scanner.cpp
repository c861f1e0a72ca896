#include "beamtrace/sensor/risley_scanner.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "sensor/detail/mechanism_preset_yaml.hpp"
#include "sensor/detail/scan_pattern_types.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegToRad = kPi / 180.0;

}  // namespace

double RisleyScannerConfig::prism_deviation_rad() const {
    return (refractive_index - 1.0) * wedge_deg * kDegToRad;
}

std::vector<std::string> RisleyScannerConfig::validate() const {
    std::vector<std::string> p;
    detail::pulse_timing_problems(pulse_rate_hz, duration_s, start_time_s, p);
    const bool wedge_ok = wedge_deg > 0.0 && wedge_deg < 45.0;
    const bool index_ok = refractive_index > 1.0 && refractive_index <= 4.0;
    if (!wedge_ok) {
        p.push_back("wedge_deg must be in (0, 45) (got " + std::to_string(wedge_deg) + ")");
    }
    if (!index_ok) {
        p.push_back("refractive_index must be in (1, 4] (got " + std::to_string(refractive_index) +
                    ")");
    }
    if (wedge_ok && index_ok && !(2.0 * prism_deviation_rad() < 0.5 * kPi)) {
        p.push_back(
            "(refractive_index - 1) x wedge_deg must be below 45 deg (the pattern's "
            "radius, twice that, below 90 deg; got " +
            std::to_string(prism_deviation_rad() / kDegToRad) + " deg)");
    }
    for (const auto& [name, rate] : {std::pair{"rotation_rate_1_hz", rotation_rate_1_hz},
                                     std::pair{"rotation_rate_2_hz", rotation_rate_2_hz}}) {
        if (!std::isfinite(rate)) {
            p.push_back(std::string(name) + " must be finite");
        }
    }
    if (rotation_rate_1_hz == 0.0 && rotation_rate_2_hz == 0.0) {
        p.push_back("rotation_rate_1_hz and rotation_rate_2_hz are both 0 (a fixed beam)");
    }
    return p;
}

RisleyScanner::RisleyScanner(RisleyScannerConfig config) : config_(std::move(config)) {
    throw_if_problems("risley scanner", config_.validate());
    pulse_count_ = whole_count(config_.duration_s * config_.pulse_rate_hz);
}

std::pair<double, double> RisleyScanner::deviation_rad(std::uint64_t i) const {
    const double n = static_cast<double>(i) / config_.pulse_rate_hz;
    const double t1 = 2.0 * kPi * detail::frac(config_.rotation_rate_1_hz * n);
    const double t2 = 2.0 * kPi * detail::frac(config_.rotation_rate_2_hz * n);
    const double delta = config_.prism_deviation_rad();
    return {delta * (std::cos(t1) + std::cos(t2)), delta * (std::sin(t1) + std::sin(t2))};
}

void RisleyScanner::generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const {
    for (std::size_t j = 0; j < count; ++j) {
        const std::uint64_t i = first + j;
        const auto [dy, dz] = deviation_rad(i);
        const double rho = std::hypot(dy, dz);
        // sin(rho) / rho scales D onto the unit sphere (1 at rho = 0, where D is 0 too).
        const double k = rho > 0.0 ? std::sin(rho) / rho : 1.0;
        const Vec3d d{std::cos(rho), dy * k, dz * k};
        out.time_s[j] = pulse_time_s(i);
        out.direction[j] = d;
        out.channel[j] = 0;
        out.scan_angle_deg[j] = static_cast<float>(std::atan2(d.y, d.x) / kDegToRad);
    }
}

namespace {

/// Reads the signed number `n[name]`, when present, into `out`.
void read_rate(detail::YamlChecker& c, const YAML::Node& n, const char* name, double& out) {
    if (n[name]) {
        c.number(n[name], detail::scanner_key(name), out);
    }
}

std::unique_ptr<ScannerSettings> parse_risley(detail::YamlChecker& c, const YAML::Node& n) {
    RisleyScannerConfig s;
    const SensorDataSheet* sheet = detail::parse_mechanism_preset(c, n, risley_presets(), s);
    detail::parse_pulse_timing(c, n, s.pulse_rate_hz, s.duration_s);
    detail::scanner_positive(c, n, "wedge_deg", s.wedge_deg);
    detail::scanner_positive(c, n, "refractive_index", s.refractive_index);
    read_rate(c, n, "rotation_rate_1_hz", s.rotation_rate_1_hz);
    read_rate(c, n, "rotation_rate_2_hz", s.rotation_rate_2_hz);
    detail::scanner_problems(c, n, s.validate());
    auto settings = std::make_unique<SettingsOf<RisleyScanner>>(std::move(s));
    settings->set_data_sheet(sheet);
    return settings;
}

constexpr std::array<std::string_view, 7> kRisleyKeys{
    "preset",           "pulse_rate_hz",      "wedge_deg",
    "refractive_index", "rotation_rate_1_hz", "rotation_rate_2_hz",
    "duration_s"};

}  // namespace

ScanPatternEntry detail::risley_scanner_entry() {
    return {"risley", "a Risley prism pair (Livox style): two turning wedges draw a rosette",
            kRisleyKeys, parse_risley};
}

}  // namespace beamtrace
