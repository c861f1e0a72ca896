#include "beamtrace/sensor/line_scanner.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>
#include <utility>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/name_table.hpp"
#include "core/simd_level.hpp"
#include "sensor/detail/line_angles.hpp"
#include "sensor/detail/mechanism_preset_yaml.hpp"
#include "sensor/detail/scan_pattern_types.hpp"
#include "sensor/detail/scanner_yaml.hpp"
#include "text/quote.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace beamtrace {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

/// Slots of the memo of directions (PulseBatch::sincos_memo): more than the pulses of a line
/// of most scanners, 96 KiB.
constexpr std::size_t kMemoSlots = 4096;

/// Where an angle's direction is kept in the memo: its place in [-max, max], so that the angles
/// of one line (a few thousand pulses) each have a slot of their own.
struct MemoSlots {
    double max_deg = 1.0;
    double slots_per_deg = 1.0;
};

/// Memo entry `e` holding the angle of bits `s_bits` (radians) and its cos and sin: as it is, or
/// computed where it holds another angle (bits, not s == key: -0.0, 0.0).
[[gnu::always_inline]] inline const SincosMemo::Entry& memo_entry(SincosMemo::Entry& e,
                                                                  std::uint64_t s_bits) {
    if (e.angle_bits != s_bits) {
        const double s = std::bit_cast<double>(s_bits);
        e.angle_bits = s_bits;
        e.cos = std::cos(s);
        e.sin = std::sin(s);
    }
    return e;
}

/// Pulse k of `out` from its angle and time: its direction (cos, sin, 0) from the memo's slot of
/// the angle.
[[gnu::always_inline]] inline void memo_pulse(SincosMemo::Entry* memo, const MemoSlots& m,
                                              double s_deg, double time_s, PulseBatch& out,
                                              std::size_t k) {
    const double s = s_deg * kDegToRad;
    const double u = std::min((s_deg + m.max_deg) * m.slots_per_deg, kMemoSlots - 1.0);
    const SincosMemo::Entry& e = memo_entry(memo[u >= 0.0 ? static_cast<std::size_t>(u) : 0],
                                            std::bit_cast<std::uint64_t>(s));
    out.time_s[k] = time_s;
    out.direction[k] = {e.cos, e.sin, 0.0};
    out.channel[k] = 0;
    out.scan_angle_deg[k] = static_cast<float>(s_deg);
}

#if defined(__x86_64__) && defined(__GNUC__)
/// memo_pulse() of the first 4 * (n / 4) angles, their radians, slots, times and scan angles
/// four at a time in AVX2 lanes (the same operations; a NaN angle takes slot 0 as there), the
/// memo one lane at a time; returns how many it did.
__attribute__((target("avx2"))) std::size_t memo_quads(SincosMemo::Entry* memo, const MemoSlots& m,
                                                       const double* angles, const double* times,
                                                       std::size_t n, PulseBatch& out,
                                                       std::size_t at) {
    const __m256d to_rad = _mm256_set1_pd(kDegToRad), max_deg = _mm256_set1_pd(m.max_deg);
    const __m256d per_deg = _mm256_set1_pd(m.slots_per_deg);
    const __m256d last = _mm256_set1_pd(kMemoSlots - 1.0);
    std::size_t j = 0;
    for (; j + 4 <= n; j += 4) {
        const __m256d deg = _mm256_loadu_pd(angles + j);
        alignas(32) std::uint64_t bits[4];
        alignas(16) std::int32_t slot[4];
        _mm256_store_pd(reinterpret_cast<double*>(bits), _mm256_mul_pd(deg, to_rad));
        // min(u, last) as std::min(u, last) orders it (a NaN u stays NaN), then NaN and
        // negatives to slot 0 (max_pd gives its second operand for a NaN).
        const __m256d u = _mm256_min_pd(last, _mm256_mul_pd(_mm256_add_pd(deg, max_deg), per_deg));
        _mm_store_si128(reinterpret_cast<__m128i*>(slot),
                        _mm256_cvttpd_epi32(_mm256_max_pd(u, _mm256_setzero_pd())));
        for (std::size_t l = 0; l < 4; ++l) {
            const SincosMemo::Entry& e = memo_entry(memo[slot[l]], bits[l]);
            Vec3d& d = out.direction[at + j + l];
            d.x = e.cos;
            d.y = e.sin;
            d.z = 0.0;
        }
        _mm256_storeu_pd(out.time_s.data() + at + j, _mm256_loadu_pd(times + j));
        std::memset(out.channel.data() + at + j, 0, 4 * sizeof(std::uint16_t));
        _mm_storeu_ps(out.scan_angle_deg.data() + at + j, _mm256_cvtpd_ps(deg));
    }
    return j;
}
#endif

constexpr NameTable<ScanWaveform, 3> kScanWaveforms{"scan waveform",
                                                    {{{ScanWaveform::sawtooth, "sawtooth"},
                                                      {ScanWaveform::sinusoid, "sinusoid"},
                                                      {ScanWaveform::triangle, "triangle"}}}};

}  // namespace

std::string_view to_string(ScanWaveform waveform) {
    return kScanWaveforms.to_string(waveform);
}

ScanWaveform parse_scan_waveform(std::string_view name) {
    return kScanWaveforms.parse(name);
}

std::vector<std::string> LineScannerConfig::validate() const {
    std::vector<std::string> p;
    detail::pulse_timing_problems(pulse_rate_hz, duration_s, start_time_s, p);
    const bool rate_ok = pulse_rate_hz > 0.0 && std::isfinite(pulse_rate_hz);
    if (!(scan_rate_hz > 0.0 && std::isfinite(scan_rate_hz))) {
        p.push_back("scan_rate_hz must be positive (got " + std::to_string(scan_rate_hz) + ")");
    } else if (rate_ok && !(2.0 * lines_per_s() <= pulse_rate_hz)) {
        p.push_back("scan_rate_hz (" + std::to_string(scan_rate_hz) + " mirror periods/s, " +
                    std::to_string(lines_per_s()) +
                    " lines/s) must leave at least two pulses per line (pulse_rate_hz " +
                    std::to_string(pulse_rate_hz) + ")");
    }
    if (!(turn_duration_s >= 0.0 && std::isfinite(turn_duration_s))) {
        p.push_back("turn_duration_s must be 0 or positive (got " +
                    std::to_string(turn_duration_s) + ")");
    } else if (turn_duration_s > 0.0 && waveform != ScanWaveform::triangle) {
        p.push_back(
            "turn_duration_s applies to the triangle waveform only (an oscillating "
            "mirror; a sinusoid turns smoothly, a sawtooth flies back)");
    } else if (turn_duration_s > 0.0 && scan_rate_hz > 0.0 && std::isfinite(scan_rate_hz) &&
               !(turn_duration_s < 1.0 / lines_per_s())) {
        p.push_back("turn_duration_s (" + std::to_string(turn_duration_s) +
                    ") must be shorter than a line (" + std::to_string(1.0 / lines_per_s()) +
                    " s)");
    }
    if (!(scan_angle_max_deg > 0.0 && scan_angle_max_deg < 90.0)) {
        p.push_back("scan_angle_max_deg must be in (0, 90) (got " +
                    std::to_string(scan_angle_max_deg) + ")");
    }
    if (waveform != ScanWaveform::sawtooth && waveform != ScanWaveform::sinusoid &&
        waveform != ScanWaveform::triangle) {
        p.push_back("waveform must be sawtooth, sinusoid or triangle");
    }
    return p;
}

LineScanner::LineScanner(LineScannerConfig config) : config_(std::move(config)) {
    throw_if_problems("line scanner", config_.validate());
    pulse_count_ = whole_count(config_.duration_s * config_.pulse_rate_hz);
    lines_per_s_ = config_.lines_per_s();
}

double LineScanner::angle_at_lines(double lines) const {
    const double a = config_.scan_angle_max_deg;
    switch (config_.waveform) {
        case ScanWaveform::sawtooth:
            return detail::sawtooth_deg(a, lines);
        case ScanWaveform::triangle:
            if (config_.turn_duration_s > 0.0) {
                return turning_angle_at_lines(lines);
            }
            return detail::triangle_deg(a, lines);
        case ScanWaveform::sinusoid:
            return -a * std::cos(2.0 * std::numbers::pi * detail::line_frac(0.5 * lines));
    }
    return 0.0;
}

double LineScanner::turning_angle_at_lines(double lines) const {
    // In line-period units (T = 1): half turn h, speed w = 2 max / (1 - h), acceleration w / h.
    const double a = config_.scan_angle_max_deg;
    const double h = 0.5 * config_.turn_duration_s * lines_per_s_;
    const double w = 2.0 * a / (1.0 - h);
    const double n = std::floor(lines);
    const double u = lines - n;
    double s = 0.0;
    if (u < h) {
        s = -a + w * u * u / (2.0 * h);
    } else if (u <= 1.0 - h) {
        s = -a + w * h / 2.0 + w * (u - h);
    } else {
        s = a - w * (1.0 - u) * (1.0 - u) / (2.0 * h);
    }
    return std::fmod(n, 2.0) == 0.0 ? s : -s;  // odd lines sweep back
}

double LineScanner::scan_angle_deg_at(double time_s) const {
    return angle_at_lines((time_s - config_.start_time_s) * lines_per_s_);
}

std::uint64_t LineScanner::line_of_pulse(std::uint64_t i) const {
    return static_cast<std::uint64_t>(
        std::floor(static_cast<double>(i) * lines_per_s_ / config_.pulse_rate_hz));
}

double LineScanner::line_start_time_s(std::uint64_t n) const {
    return config_.start_time_s + static_cast<double>(n) / lines_per_s_;
}

void LineScanner::generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const {
    std::vector<SincosMemo::Entry>& memo = out.sincos_memo.entries;
    if (memo.size() != kMemoSlots) {
        memo.assign(kMemoSlots, {});
    }
    const double a = config_.scan_angle_max_deg;
    const MemoSlots slots{a, static_cast<double>(kMemoSlots) / (2.0 * a)};
    // Sawtooth and triangle without turns: the angles and times of a chunk of pulses in lanes
    // first (detail::line_angles_lanes, the same bits), then the directions from the memo, four
    // pulses' slots at a time in lanes where the CPU has them.
    const bool lanes = config_.waveform == ScanWaveform::sawtooth ||
                       (config_.waveform == ScanWaveform::triangle && config_.turn_duration_s <= 0);
    const detail::LineAngleParams params{config_.start_time_s, config_.pulse_rate_hz, lines_per_s_,
                                         a, config_.waveform == ScanWaveform::triangle};
    constexpr std::size_t kChunk = 256;
    std::array<double, kChunk> angles{}, times{};
    for (std::size_t c = 0; c < count; c += kChunk) {
        const std::size_t n = std::min(kChunk, count - c);
        std::size_t done = 0;
        if (lanes) {
            done = detail::line_angles_lanes(params, first + c, n, angles.data(), times.data());
        }
        for (std::size_t j = done; j < n; ++j) {
            const std::uint64_t i = first + c + j;
            // The same expression as line_of_pulse, so a pulse's angle and line always agree.
            angles[j] = angle_at_lines(detail::lines_of_pulse(params, i));
            times[j] = pulse_time_s(i);
        }
        std::size_t memo_done = 0;
#if defined(__x86_64__) && defined(__GNUC__)
        if (detail::cpu_simd_level() != detail::SimdLevel::scalar) {
            memo_done = memo_quads(memo.data(), slots, angles.data(), times.data(), n, out, c);
        }
#endif
        for (std::size_t j = memo_done; j < n; ++j) {
            memo_pulse(memo.data(), slots, angles[j], times[j], out, c + j);
        }
    }
}

namespace {

std::unique_ptr<ScannerSettings> parse_line(detail::YamlChecker& c, const YAML::Node& n) {
    double duration = 0.0;
    const bool has_duration =
        n["duration_s"] && c.number(n["duration_s"], "scanner.duration_s", duration);
    LineScannerConfig s;
    const SensorDataSheet* sheet = detail::parse_mechanism_preset(c, n, line_presets(), s);
    detail::scanner_positive(c, n, "pulse_rate_hz", s.pulse_rate_hz);
    detail::scanner_positive(c, n, "scan_rate_hz", s.scan_rate_hz);
    detail::scanner_positive(c, n, "scan_angle_max_deg", s.scan_angle_max_deg);
    if (const auto d = n["turn_duration_s"];
        d && c.number(d, "scanner.turn_duration_s", s.turn_duration_s) && s.turn_duration_s < 0) {
        c.error(d, "scanner.turn_duration_s", "must not be negative");
    }
    if (const auto w = n["waveform"]) {
        try {
            // A name longer than the quote limit matches none, so the error quotes it clipped.
            s.waveform = parse_scan_waveform(w.IsScalar() ? detail::clip_value(w.Scalar()) : "");
        } catch (const ConfigError& e) {
            c.error(w, "scanner.waveform", e.what());
        }
    }
    if (has_duration) {
        s.duration_s = duration;
    }
    detail::scanner_problems(c, n, s.validate());
    auto settings = std::make_unique<SettingsOf<LineScanner>>(std::move(s));
    settings->set_data_sheet(sheet);
    return settings;
}

constexpr std::array<std::string_view, 7> kLineKeys{
    "preset",   "pulse_rate_hz",   "scan_rate_hz", "scan_angle_max_deg",
    "waveform", "turn_duration_s", "duration_s"};

}  // namespace

ScanPatternEntry detail::line_scanner_entry() {
    return {"line", "an airborne line scanner: one beam swept across track by a mirror", kLineKeys,
            parse_line};
}

}  // namespace beamtrace
