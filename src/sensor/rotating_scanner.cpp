#include "beamtrace/sensor/rotating_scanner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <utility>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/beam_table.hpp"
#include "beamtrace/sensor/rotating_presets.hpp"
#include "sensor/detail/rotating_lanes.hpp"
#include "sensor/detail/scan_pattern_types.hpp"
#include "sensor/detail/scanner_yaml.hpp"

namespace beamtrace {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

/// n evenly spaced values from lo to hi inclusive.
std::vector<double> evenly(double lo, double hi, int n) {
    std::vector<double> v(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        v[static_cast<std::size_t>(i)] =
            i == n - 1 ? hi : lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1);
    }
    return v;
}

RotatingScannerConfig preset(std::vector<double> elevations_deg, double resolution_deg) {
    RotatingScannerConfig c;
    c.beam_elevations_deg = std::move(elevations_deg);
    c.rotation_rate_hz = 10.0;
    c.azimuth_resolution_deg = resolution_deg;
    c.duration_s = 0.1;  // one revolution
    return c;
}

/// The problems of the per-beam tables besides the elevations: lengths, timing, channels.
void beam_table_problems(const RotatingScannerConfig& c, std::vector<std::string>& p) {
    const std::size_t beams = c.beam_elevations_deg.size();
    if (!c.beam_time_offsets_s.empty() && c.beam_time_offsets_s.size() != beams) {
        p.push_back("beam_time_offsets_s must be empty or have one value per beam (" +
                    std::to_string(beams) + "), got " +
                    std::to_string(c.beam_time_offsets_s.size()));
    } else if (!c.beam_time_offsets_s.empty() && p.empty()) {
        const double period = 1.0 / c.firing_rate_hz();
        for (std::size_t b = 0; b < beams; ++b) {
            const double t = c.beam_time_offsets_s[b];
            if (!(t >= 0.0 && t < period)) {
                p.push_back("beam_time_offsets_s[" + std::to_string(b) +
                            "] must be in [0, firing period " + std::to_string(period) +
                            " s) (got " + std::to_string(t) + ")");
            } else if (b > 0 && t < c.beam_time_offsets_s[b - 1]) {
                p.push_back("beam_time_offsets_s[" + std::to_string(b) +
                            "] must not be earlier than the beam before (rows are in firing "
                            "order)");
            }
        }
    }
    if (!c.beam_channels.empty() && c.beam_channels.size() != beams) {
        p.push_back("beam_channels must be empty or have one value per beam (" +
                    std::to_string(beams) + "), got " + std::to_string(c.beam_channels.size()));
    } else if (!c.beam_channels.empty()) {
        std::vector<std::uint16_t> sorted = c.beam_channels;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
            p.push_back("beam_channels must be distinct");
        }
    }
}

}  // namespace

std::vector<std::string> RotatingScannerConfig::validate() const {
    std::vector<std::string> p;
    const std::size_t beams = beam_elevations_deg.size();
    if (beams == 0) {
        p.push_back("beam_elevations_deg must list at least one beam");
    }
    if (beams > std::size_t{65536}) {
        p.push_back("at most 65536 beams (channels are 16-bit), got " + std::to_string(beams));
    }
    for (std::size_t b = 0; b < beams; ++b) {
        const double e = beam_elevations_deg[b];
        if (!(e >= -90.0 && e <= 90.0)) {
            p.push_back("beam_elevations_deg[" + std::to_string(b) +
                        "] must be in [-90, 90] (got " + std::to_string(e) + ")");
        }
    }
    if (!beam_azimuth_offsets_deg.empty() && beam_azimuth_offsets_deg.size() != beams) {
        p.push_back("beam_azimuth_offsets_deg must be empty or have one value per beam (" +
                    std::to_string(beams) + "), got " +
                    std::to_string(beam_azimuth_offsets_deg.size()));
    }
    for (std::size_t b = 0; b < beam_azimuth_offsets_deg.size(); ++b) {
        if (!std::isfinite(beam_azimuth_offsets_deg[b])) {
            p.push_back("beam_azimuth_offsets_deg[" + std::to_string(b) + "] must be finite");
        }
    }
    if (!(rotation_rate_hz > 0.0 && std::isfinite(rotation_rate_hz))) {
        p.push_back("rotation_rate_hz must be positive (got " + std::to_string(rotation_rate_hz) +
                    ")");
    }
    if (!(azimuth_resolution_deg > 0.0 && azimuth_resolution_deg <= 360.0)) {
        p.push_back("azimuth_resolution_deg must be in (0, 360] (got " +
                    std::to_string(azimuth_resolution_deg) + ")");
    }
    if (!(firing_period_s >= 0.0 && std::isfinite(firing_period_s))) {
        p.push_back("firing_period_s must be 0 or positive (got " +
                    std::to_string(firing_period_s) + ")");
    } else if (firing_period_s > 0.0 && !(azimuth_step_deg() <= 360.0)) {
        p.push_back("rotation_rate_hz x 360 x firing_period_s must be at most 360 degrees");
    }
    if (!(preset_range_min_m >= 0.0 && preset_range_max_m >= 0.0 &&
          std::isfinite(preset_range_max_m)) ||
        (preset_range_max_m > 0.0 && !(preset_range_max_m > preset_range_min_m))) {
        p.push_back("preset_range_min_m and preset_range_max_m must be 0 (none) or 0 <= min < max");
    }
    if (!std::isfinite(start_azimuth_deg)) {
        p.push_back("start_azimuth_deg must be finite");
    }
    if (!(duration_s > 0.0 && std::isfinite(duration_s))) {
        p.push_back("duration_s must be positive (got " + std::to_string(duration_s) + ")");
    }
    if (!std::isfinite(start_time_s)) {
        p.push_back("start_time_s must be finite");
    }
    beam_table_problems(*this, p);
    if (p.empty()) {
        const double pulses = duration_s * pulse_rate_hz();
        if (!(pulses <= 9.0e15)) {
            p.push_back("duration_s x pulse rate must be below 9e15 pulses");
        } else if (firing_count() == 0) {
            p.push_back("duration_s (" + std::to_string(duration_s) +
                        ") is shorter than one firing (" + std::to_string(1.0 / firing_rate_hz()) +
                        " s)");
        }
    }
    return p;
}

std::uint64_t RotatingScannerConfig::firing_count() const {
    return whole_count(duration_s * firing_rate_hz());
}

RotatingScannerConfig vlp16() {
    return preset({-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15}, 0.2);
}

RotatingScannerConfig hdl32() {
    return preset(evenly(-30.67, 10.67, 32), 0.16);
}

RotatingScannerConfig hdl64() {
    return preset(evenly(-24.9, 2.0, 64), 0.18);
}

RotatingScannerConfig os128() {
    return preset(evenly(-22.5, 22.5, 128), 360.0 / 1024.0);
}

RotatingScanner::RotatingScanner(RotatingScannerConfig config) : config_(std::move(config)) {
    throw_if_problems("rotating scanner", config_.validate());
    const std::size_t beams = beam_count();
    pulse_count_ = config_.firing_count() * beams;
    pulse_rate_hz_ = config_.pulse_rate_hz();
    step_deg_ = config_.azimuth_step_deg();
    period_s_ =
        config_.firing_period_s > 0.0 ? config_.firing_period_s : 1.0 / config_.firing_rate_hz();
    const double per_rev = 360.0 / step_deg_;
    const double rounded = std::round(per_rev);
    if (std::abs(per_rev - rounded) <= 1e-9 * rounded) {
        firings_per_revolution_ = static_cast<std::uint64_t>(rounded);
    }
    if (config_.beam_azimuth_offsets_deg.empty()) {
        config_.beam_azimuth_offsets_deg.assign(beams, 0.0);
    }
    cos_elevation_.resize(beams);
    sin_elevation_.resize(beams);
    within_deg_.resize(beams);
    cos_beam_azimuth_.resize(beams);
    sin_beam_azimuth_.resize(beams);
    const double sign = config_.spin_clockwise ? -1.0 : 1.0;
    const double deg_per_s = config_.rotation_rate_hz * 360.0;
    for (std::size_t b = 0; b < beams; ++b) {
        const double e = config_.beam_elevations_deg[b] * kDegToRad;
        cos_elevation_[b] = std::cos(e);
        sin_elevation_[b] = std::sin(e);
        within_deg_[b] = config_.beam_time_offsets_s.empty()
                             ? step_deg_ * static_cast<double>(b) / static_cast<double>(beams)
                             : deg_per_s * config_.beam_time_offsets_s[b];
        const double a = (sign * within_deg_[b] + config_.beam_azimuth_offsets_deg[b]) * kDegToRad;
        cos_beam_azimuth_[b] = std::cos(a);
        sin_beam_azimuth_[b] = std::sin(a);
    }
}

double RotatingScanner::pulse_time_s(std::uint64_t i) const {
    if (config_.beam_time_offsets_s.empty() || i >= pulse_count_) {
        return ScanPattern::pulse_time_s(i);
    }
    const std::uint64_t beams = beam_count();
    return beam_time_s(i, i / beams, static_cast<std::size_t>(i % beams));
}

double RotatingScanner::beam_time_s(std::uint64_t i, std::uint64_t firing, std::size_t b) const {
    if (config_.beam_time_offsets_s.empty()) {
        return ScanPattern::pulse_time_s(i);
    }
    return config_.start_time_s + static_cast<double>(firing) * period_s_ +
           config_.beam_time_offsets_s[b];
}

void RotatingScanner::generate_pulses(std::uint64_t first, std::size_t count,
                                      PulseBatch& out) const {
    const std::uint64_t beams = beam_count();
    const double res = step_deg_;
    // Uniform times (no timing table): ScanPattern::pulse_time_s's, without its two virtual
    // calls a pulse; the firing's beams then four at a time in lanes where the CPU has them.
    const bool uniform_times = config_.beam_time_offsets_s.empty();
    detail::FiringParams f;
    f.start_azimuth_deg = config_.start_azimuth_deg;
    f.sign = config_.spin_clockwise ? -1.0 : 1.0;
    f.start_s = config_.start_time_s;
    f.pulse_rate_hz = pulse_rate_hz_;
    f.within_deg = within_deg_.data();
    f.offset_deg = config_.beam_azimuth_offsets_deg.data();
    f.cos_beam = cos_beam_azimuth_.data();
    f.sin_beam = sin_beam_azimuth_.data();
    f.cos_elevation = cos_elevation_.data();
    f.sin_elevation = sin_elevation_.data();
    f.channels = config_.beam_channels.empty() ? nullptr : config_.beam_channels.data();
    // Firing k and beam b of pulse first + j, counted up rather than divided. The firing's
    // heading, as cos/sin, is computed once per firing: a beam's direction is the heading
    // rotated by the beam's own azimuth (angle addition, within 1e-15 of a direct sincos).
    std::uint64_t k = first / beams;
    auto b = static_cast<std::size_t>(first % beams);
    for (std::size_t j = 0; j < count; k += 1, b = 0) {
        f.head_deg = firings_per_revolution_ > 0
                         ? static_cast<double>(k % firings_per_revolution_) * res
                         : std::fmod(static_cast<double>(k) * res, 360.0);
        const double head = (f.start_azimuth_deg + f.sign * f.head_deg) * kDegToRad;
        f.cos_head = std::cos(head);
        f.sin_head = std::sin(head);
        const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(beams) - b, count - j);
        std::size_t done = uniform_times ? detail::firing_lanes(f, first + j, b, n, out, j) : 0;
        for (; done < n; ++done) {
            const std::uint64_t i = first + j + done;
            const double time_s = uniform_times ? uniform_time_s(f.start_s, f.pulse_rate_hz, i)
                                                : beam_time_s(i, k, b + done);
            detail::firing_pulse(f, time_s, b + done, out, j + done);
        }
        j += n;
    }
}

namespace {

/// A list of numbers at `key` into `out` (replaced); false (after reporting) when it is not one.
bool number_list(detail::YamlChecker& c, const YAML::Node& v, const std::string& key,
                 std::vector<double>& out) {
    out.clear();
    if (!v.IsSequence() || v.size() == 0) {
        c.error(v, key, "expected a list of angles");
        return false;
    }
    for (std::size_t i = 0; i < v.size(); ++i) {
        double e = 0;
        if (c.number(v[i], key + "[" + std::to_string(i) + "]", e)) {
            out.push_back(e);
        }
    }
    return true;
}

/// `beam_table`: a CSV file relative to the survey file (beam_table.hpp).
void parse_beam_table(detail::YamlChecker& c, const YAML::Node& t, RotatingScannerConfig& s) {
    if (!t.IsScalar() || t.Scalar().empty()) {
        c.error(t, "scanner.beam_table", "expected a CSV file name");
        return;
    }
    const std::filesystem::path path = c.source().parent_path() / t.Scalar();
    if (!c.existing_file(t, "scanner.beam_table", path)) {
        return;
    }
    try {
        read_beam_table_csv(path, s);
    } catch (const InputError& e) {
        c.error(t, "scanner.beam_table", e.what());
    }
}

/// `preset` (replacing the whole config), then a table: `beam_table` or `beam_elevations_deg`
/// (+ `beam_azimuth_offsets_deg`), which replace the preset's rows.
void parse_beams(detail::YamlChecker& c, const YAML::Node& n, RotatingScannerConfig& s) {
    if (const auto p = n["preset"]) {
        const RotatingPreset* preset = find_rotating_preset(p.IsScalar() ? p.Scalar() : "");
        if (preset != nullptr) {
            s = preset->make();
        } else {
            c.error(p, "scanner.preset",
                    "unknown preset (expected " + rotating_preset_names() + ")");
        }
    }
    if (n["beam_table"] && n["beam_elevations_deg"]) {
        c.error(n, "scanner", "give beam_table or beam_elevations_deg, not both");
        return;
    }
    if (const auto t = n["beam_table"]) {
        parse_beam_table(c, t, s);
    }
    if (const auto b = n["beam_elevations_deg"]) {
        s.beam_azimuth_offsets_deg.clear();
        s.beam_time_offsets_s.clear();
        s.beam_channels.clear();
        if (!number_list(c, b, "scanner.beam_elevations_deg", s.beam_elevations_deg)) {
            return;
        }
    }
    if (const auto a = n["beam_azimuth_offsets_deg"]) {
        (void)number_list(c, a, "scanner.beam_azimuth_offsets_deg", s.beam_azimuth_offsets_deg);
    }
}

std::unique_ptr<ScannerSettings> parse_rotating(detail::YamlChecker& c, const YAML::Node& n) {
    double duration = 0.0;
    const bool has_duration =
        n["duration_s"] && c.number(n["duration_s"], "scanner.duration_s", duration);
    RotatingScannerConfig s = vlp16();
    parse_beams(c, n, s);
    detail::scanner_positive(c, n, "rotation_rate_hz", s.rotation_rate_hz);
    if (n["azimuth_resolution_deg"] && n["firing_period_s"]) {
        c.error(n, "scanner", "give azimuth_resolution_deg or firing_period_s, not both");
    }
    if (n["azimuth_resolution_deg"]) {
        s.firing_period_s = 0.0;  // the step the survey asks for, not the preset's clock
        detail::scanner_positive(c, n, "azimuth_resolution_deg", s.azimuth_resolution_deg);
    }
    detail::scanner_positive(c, n, "firing_period_s", s.firing_period_s);
    if (const auto a = n["start_azimuth_deg"]) {
        (void)c.number(a, "scanner.start_azimuth_deg", s.start_azimuth_deg);
    }
    if (const auto cw = n["spin_clockwise"]) {
        c.boolean(cw, "scanner.spin_clockwise", s.spin_clockwise);
    }
    if (has_duration) {
        s.duration_s = duration;
    }
    detail::scanner_problems(c, n, s.validate());
    return std::make_unique<SettingsOf<RotatingScanner>>(std::move(s));
}

constexpr std::array<std::string_view, 10> kRotatingKeys{"preset",
                                                         "beam_table",
                                                         "beam_elevations_deg",
                                                         "beam_azimuth_offsets_deg",
                                                         "rotation_rate_hz",
                                                         "azimuth_resolution_deg",
                                                         "firing_period_s",
                                                         "spin_clockwise",
                                                         "start_azimuth_deg",
                                                         "duration_s"};

}  // namespace

ScanPatternEntry detail::rotating_scanner_entry() {
    return {"rotating", "a spinning multi-beam head (Velodyne, Ouster, Hesai)", kRotatingKeys,
            parse_rotating};
}

}  // namespace beamtrace
