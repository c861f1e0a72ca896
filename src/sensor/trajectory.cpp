#include "beamtrace/sensor/trajectory.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <string_view>
#include <utility>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/scan_pattern.hpp"
#include "core/simd_level.hpp"
#include "text/file_bytes.hpp"
#include "text/quote.hpp"
#include "text/row_writer.hpp"
#include "text/text_scan.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace beamtrace {
namespace {

constexpr std::array<std::string_view, 7> kColumns = {"time_s", "x",     "y",  "z",
                                                      "roll",   "pitch", "yaw"};
constexpr std::string_view kHeader = "time_s,x,y,z,roll,pitch,yaw";
/// The largest trajectory CSV file read (docs/survey.md): 512 MiB, some 6 million samples.
constexpr std::size_t kMaxFileBytes = std::size_t{512} << 20;

[[nodiscard]] double time_tolerance_s(double t) {
    return 1e-9 * std::max(1.0, std::abs(t));
}

/// `t` clamped into [start, end] when within the tolerance of it; throws ConfigError otherwise.
[[nodiscard]] double checked_time(std::string_view what, double t, double start, double end) {
    if (t >= start && t <= end) {
        return t;
    }
    if (t < start && start - t <= time_tolerance_s(t)) {
        return start;
    }
    if (t > end && t - end <= time_tolerance_s(t)) {
        return end;
    }
    throw ConfigError(std::string(what) + ": time " + std::to_string(t) +
                      " s is outside the trajectory's range [" + std::to_string(start) + ", " +
                      std::to_string(end) + "] s");
}

/// Index k of the segment [times[k], times[k+1]] that holds t (times has at least 2 entries;
/// t within [front, back]); at an inner knot, the segment that starts there.
[[nodiscard]] std::size_t segment_of(const std::vector<double>& times, double t) {
    const auto it = std::upper_bound(times.begin(), times.end(), t);
    const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - times.begin() - 1, 0));
    return std::min(k, times.size() - 2);
}

[[nodiscard]] bool finite(const Vec3d& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

[[nodiscard]] bool finite(const RollPitchYaw& a) {
    return std::isfinite(a.roll_rad) && std::isfinite(a.pitch_rad) && std::isfinite(a.yaw_rad);
}

[[nodiscard]] Vec3d lerp(const Vec3d& a, const Vec3d& b, double f) {
    return a + (b - a) * f;
}

/// Where along leg [t0, t1] the time t lies (0 at its start, 1 at its end).
[[gnu::always_inline]] inline double leg_fraction(double t, double t0, double t1) {
    return (t - t0) / (t1 - t0);
}

/// The point at fraction f of the leg from w0 to w1 (its end from f = 1 on).
[[gnu::always_inline]] inline Vec3d point_on_leg(double f, const Vec3d& w0, const Vec3d& w1) {
    return f >= 1.0 ? w1 : lerp(w0, w1, f);
}

/// The leg of a linear flight (waypoint times `times`) that a run of times falls on: pulse times
/// mostly stay on one leg, so the leg is kept while a time is on it (the leg segment_of would
/// find) and searched again otherwise. Its times in members, which a batch's loop keeps in
/// registers (the stores of each pose's doubles may alias the trajectory's vectors).
struct LegCursor {
    const std::vector<double>* times;
    double start, end;  ///< the flight's
    bool have_leg = false, last_leg = false;
    std::size_t k = 0;  ///< the leg: [times[k], times[k + 1]]
    double t0 = 0.0, t1 = 0.0;

    explicit LegCursor(const std::vector<double>& waypoint_times)
        : times(&waypoint_times), start(waypoint_times.front()), end(waypoint_times.back()) {}

    /// Time t (within the flight's range, or within its tolerance: then its end) as used, after
    /// moving to its leg; `moved`: whether the leg changed. Throws ConfigError past the range.
    [[gnu::always_inline]] double move_to(double t, bool& moved) {
        if (!(t >= start && t <= end)) {
            t = checked_time("linear legs", t, start, end);
        }
        moved = !have_leg || !(t0 <= t && (t < t1 || last_leg));
        if (moved) {
            k = segment_of(*times, t);
            have_leg = true;
            last_leg = k + 2 == times->size();
            t0 = (*times)[k];
            t1 = (*times)[k + 1];
        }
        return t;
    }
};

#if defined(__x86_64__) && defined(__GNUC__)
/// A leg's ends and attitude as vectors: x, y, z (and 0) of its start, of its end and of end
/// less start (point_on_leg's b - a); w, x, y, z of the attitude.
struct LegLanes {
    __m256d a, b, d, q;
};

__attribute__((target("avx2"))) inline LegLanes leg_lanes(const Vec3d& w0, const Vec3d& w1,
                                                          const Quat& q) {
    LegLanes l;
    l.a = _mm256_setr_pd(w0.x, w0.y, w0.z, 0.0);
    l.b = _mm256_setr_pd(w1.x, w1.y, w1.z, 0.0);
    l.d = _mm256_sub_pd(l.b, l.a);
    l.q = _mm256_setr_pd(q.w, q.x, q.y, q.z);
    return l;
}

/// LinearLegs::poses_at() without attitudes along the legs (each leg's own attitude), where the
/// CPU has AVX2: point_on_leg() with x, y and z in the lanes of one vector (the same operations,
/// so the same bits), each pose stored as two vectors (the position's, whose last lane the
/// attitude's then overwrites).
__attribute__((target("avx2"))) void straight_poses_avx2(const std::vector<double>& times,
                                                         const std::vector<Vec3d>& waypoints,
                                                         const std::vector<Quat>& attitudes,
                                                         std::span<const double> times_s,
                                                         std::span<Pose> out) {
    static_assert(offsetof(Pose, position_m) == 0 && offsetof(Pose, attitude) == 24 &&
                  offsetof(Vec3d, z) == 16 && offsetof(Quat, z) == 24);
    LegCursor legs(times);
    LegLanes leg{};
    for (std::size_t i = 0; i < times_s.size(); ++i) {
        bool moved = false;
        const double t = legs.move_to(times_s[i], moved);
        if (moved) {
            leg = leg_lanes(waypoints[legs.k], waypoints[legs.k + 1], attitudes[legs.k]);
        }
        const double f = leg_fraction(t, legs.t0, legs.t1);
        const __m256d p =
            f >= 1.0 ? leg.b : _mm256_add_pd(leg.a, _mm256_mul_pd(leg.d, _mm256_set1_pd(f)));
        auto* pose = reinterpret_cast<double*>(&out[i]);
        _mm256_storeu_pd(pose, p);
        _mm256_storeu_pd(pose + 3, leg.q);
    }
}
#endif

}  // namespace

bool Trajectory::covers(double first_s, double last_s) const {
    const double start = start_time_s(), end = end_time_s();
    return first_s <= last_s && first_s >= start - time_tolerance_s(first_s) &&
           last_s <= end + time_tolerance_s(last_s);
}

// --- StaticPlatform ------------------------------------------------------------------------

StaticPlatform::StaticPlatform(Pose pose, double start_time_s, double end_time_s)
    : pose_(pose), start_(start_time_s), end_(end_time_s) {
    std::vector<std::string> p;
    if (!finite(pose_.position_m)) {
        p.push_back("position must be finite");
    }
    if (std::isnan(start_) || std::isnan(end_) || !(start_ <= end_)) {
        p.push_back("the time range must satisfy start <= end");
    }
    throw_if_problems("static platform", p);
}

Pose StaticPlatform::pose_at(double time_s) const {
    static_cast<void>(checked_time("static platform", time_s, start_, end_));
    return pose_;
}

// --- LinearLegs ----------------------------------------------------------------------------

std::vector<std::string> LinearLegsConfig::validate() const {
    std::vector<std::string> p;
    if (waypoints_m.size() < 2) {
        p.push_back("at least 2 waypoints are needed (got " + std::to_string(waypoints_m.size()) +
                    ")");
    }
    for (std::size_t k = 0; k < waypoints_m.size(); ++k) {
        if (!finite(waypoints_m[k])) {
            p.push_back("waypoint " + std::to_string(k) + " must be finite");
        } else if (k > 0 && finite(waypoints_m[k - 1]) && waypoints_m[k] == waypoints_m[k - 1]) {
            p.push_back("waypoint " + std::to_string(k) + " repeats waypoint " +
                        std::to_string(k - 1) + " (a leg of zero length)");
        }
    }
    if (!attitudes.empty() && attitudes.size() != waypoints_m.size()) {
        p.push_back("attitudes must be empty or have one per waypoint (" +
                    std::to_string(waypoints_m.size()) + "), got " +
                    std::to_string(attitudes.size()));
    }
    for (std::size_t k = 0; k < attitudes.size(); ++k) {
        if (!finite(attitudes[k])) {
            p.push_back("attitude " + std::to_string(k) + " must be finite");
        }
    }
    if (!(speed_mps > 0.0 && std::isfinite(speed_mps))) {
        p.push_back("speed_mps must be positive (got " + std::to_string(speed_mps) + ")");
    }
    if (!std::isfinite(start_time_s)) {
        p.push_back("start_time_s must be finite");
    }
    return p;
}

LinearLegs::LinearLegs(LinearLegsConfig config) : config_(std::move(config)) {
    throw_if_problems("linear legs", config_.validate());
    const auto& w = config_.waypoints_m;
    times_s_.resize(w.size());
    times_s_[0] = config_.start_time_s;
    double path_m = 0.0;
    for (std::size_t k = 1; k < w.size(); ++k) {
        path_m += length(w[k] - w[k - 1]);
        times_s_[k] = config_.start_time_s + path_m / config_.speed_mps;
        if (!(times_s_[k] > times_s_[k - 1])) {
            throw ConfigError("linear legs: leg " + std::to_string(k - 1) +
                              " is too short to take any time at this speed and start time");
        }
    }
    if (!config_.attitudes.empty()) {
        for (const auto& a : config_.attitudes) {
            attitude_.push_back(Quat::from_rpy(a));
        }
        return;
    }
    // Facing along each leg: the heading of its horizontal direction, vertical legs borrowing
    // the previous (else the next) leg's heading.
    const std::size_t legs = w.size() - 1;
    std::vector<double> yaw(legs, 0.0);
    std::vector<bool> known(legs, false);
    for (std::size_t k = 0; k < legs; ++k) {
        const Vec3d d = w[k + 1] - w[k];
        if (d.x != 0.0 || d.y != 0.0) {
            yaw[k] = std::atan2(-d.y, d.x);
            known[k] = true;
        }
    }
    for (std::size_t k = 1; k < legs; ++k) {
        if (!known[k] && known[k - 1]) {
            yaw[k] = yaw[k - 1];
            known[k] = true;
        }
    }
    for (std::size_t k = legs - 1; k-- > 0;) {
        if (!known[k] && known[k + 1]) {
            yaw[k] = yaw[k + 1];
            known[k] = true;
        }
    }
    for (const double y : yaw) {
        attitude_.push_back(Quat::from_rpy({0.0, 0.0, y}));
    }
}

Pose LinearLegs::pose_at(double time_s) const {
    const double t = checked_time("linear legs", time_s, start_time_s(), end_time_s());
    return pose_on_leg(t, segment_of(times_s_, t));
}

Pose LinearLegs::pose_on_leg(double t, std::size_t k) const {
    Pose pose;
    pose_on_leg_into(t, k, pose);
    return pose;
}

[[gnu::always_inline]] inline void LinearLegs::pose_on_leg_into(double t, std::size_t k,
                                                                Pose& pose) const {
    const double f = leg_fraction(t, times_s_[k], times_s_[k + 1]);
    const auto& w = config_.waypoints_m;
    pose.position_m = point_on_leg(f, w[k], w[k + 1]);
    if (config_.attitudes.empty()) {
        pose.attitude = attitude_[k];
    } else {
        pose.attitude = f <= 0.0   ? attitude_[k]
                        : f >= 1.0 ? attitude_[k + 1]
                                   : slerp(attitude_[k], attitude_[k + 1], f);
    }
}

// --- SampledTrajectory ---------------------------------------------------------------------

SampledTrajectory::SampledTrajectory(std::vector<TrajectorySample> samples)
    : samples_(std::move(samples)) {
    std::vector<std::string> p;
    if (samples_.empty()) {
        p.push_back("no samples");
    }
    for (std::size_t k = 0; k < samples_.size(); ++k) {
        const auto& s = samples_[k];
        const std::string row = "sample " + std::to_string(k);
        if (!std::isfinite(s.time_s) || !finite(s.position_m) || !finite(s.attitude)) {
            p.push_back(row + " has a non-finite value");
        } else if (k > 0 && std::isfinite(samples_[k - 1].time_s) &&
                   !(s.time_s > samples_[k - 1].time_s)) {
            p.push_back(row + ": time " + std::to_string(s.time_s) + " s is not after sample " +
                        std::to_string(k - 1) + "'s " + std::to_string(samples_[k - 1].time_s) +
                        " s (times must increase strictly)");
        }
    }
    throw_if_problems("sampled trajectory", p);
    attitude_.reserve(samples_.size());
    for (const auto& s : samples_) {
        attitude_.push_back(Quat::from_rpy(s.attitude));
    }
}

Pose SampledTrajectory::pose_at(double time_s) const {
    const double t = checked_time("sampled trajectory", time_s, start_time_s(), end_time_s());
    if (samples_.size() == 1) {
        return {samples_[0].position_m, attitude_[0]};
    }
    const auto it =
        std::upper_bound(samples_.begin(), samples_.end(), t,
                         [](double v, const TrajectorySample& s) { return v < s.time_s; });
    std::size_t k =
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - samples_.begin() - 1, 0));
    k = std::min(k, samples_.size() - 2);
    const auto& a = samples_[k];
    const auto& b = samples_[k + 1];
    const double f = (t - a.time_s) / (b.time_s - a.time_s);
    if (f <= 0.0) {
        return {a.position_m, attitude_[k]};
    }
    if (f >= 1.0) {
        return {b.position_m, attitude_[k + 1]};
    }
    return {lerp(a.position_m, b.position_m, f), slerp(attitude_[k], attitude_[k + 1], f)};
}

// --- Attitude conversion -------------------------------------------------------------------

RollPitchYaw to_rpy(const Quat& attitude) {
    // to_matrix() is the column-vector matrix M (world = M d); the report's R = Rx Ry Rz acts
    // on row vectors, so R = M^T: R(i, j) = M(j, i).
    const Mat3 m = attitude.normalized().to_matrix();
    const double r02 = std::clamp(m(2, 0), -1.0, 1.0);
    RollPitchYaw rpy;
    rpy.pitch_rad = std::asin(r02);
    if (std::abs(r02) < 1.0 - 1e-12) {
        rpy.yaw_rad = std::atan2(-m(1, 0), m(0, 0));
        rpy.roll_rad = std::atan2(-m(2, 1), m(2, 2));
    } else {
        rpy.roll_rad = 0.0;
        rpy.yaw_rad = std::atan2(m(0, 1), m(1, 1));
    }
    return rpy;
}

// --- CSV -----------------------------------------------------------------------------------

SampledTrajectory read_trajectory_csv(const std::filesystem::path& path) {
    const std::string file = path.string();
    const std::string bytes = detail::read_bounded_file(path, "trajectory file", kMaxFileBytes);
    std::string_view text = bytes;
    std::vector<TrajectorySample> samples;
    bool have_header = false;
    long line_no = 0;
    std::array<std::string_view, kColumns.size()> fields;
    while (!text.empty()) {
        const std::size_t eol = text.find('\n');
        std::string_view line = text.substr(0, eol);
        text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
        ++line_no;
        while (!line.empty() && detail::is_blank(line.front())) {
            line.remove_prefix(1);
        }
        while (!line.empty() && detail::is_blank(line.back())) {
            line.remove_suffix(1);
        }
        if (line.empty() || line.front() == '#') {
            continue;
        }
        std::size_t n = 0;
        for (std::string_view rest = line;; ++n) {
            const std::size_t comma = rest.find(',');
            std::string_view field = rest.substr(0, comma);
            while (!field.empty() && detail::is_blank(field.front())) {
                field.remove_prefix(1);
            }
            while (!field.empty() && detail::is_blank(field.back())) {
                field.remove_suffix(1);
            }
            if (n < fields.size()) {
                fields[n] = field;
            }
            if (comma == std::string_view::npos) {
                ++n;
                break;
            }
            rest.remove_prefix(comma + 1);
        }
        if (!have_header) {
            if (n != kColumns.size() ||
                !std::equal(kColumns.begin(), kColumns.end(), fields.begin())) {
                throw InputError(file, line_no,
                                 "expected the header '" + std::string(kHeader) + "'");
            }
            have_header = true;
            continue;
        }
        if (n != kColumns.size()) {
            throw InputError(file, line_no,
                             "expected " + std::to_string(kColumns.size()) + " fields (" +
                                 std::string(kHeader) + "), got " + std::to_string(n));
        }
        std::array<double, kColumns.size()> v{};
        for (std::size_t c = 0; c < v.size(); ++c) {
            if (!detail::parse_number(fields[c], v[c]) || !std::isfinite(v[c])) {
                throw InputError(file, line_no,
                                 "field '" + std::string(kColumns[c]) +
                                     "' is not a finite number: " + detail::quote_value(fields[c]));
            }
        }
        if (!samples.empty() && !(v[0] > samples.back().time_s)) {
            throw InputError(file, line_no,
                             "time " + detail::clip_value(fields[0]) +
                                 " is not after the previous sample's (times must increase "
                                 "strictly)");
        }
        samples.push_back({v[0], {v[1], v[2], v[3]}, {v[4], v[5], v[6]}});
    }
    if (!have_header) {
        throw InputError(
            file, "empty trajectory file (expected the header '" + std::string(kHeader) + "')");
    }
    if (samples.empty()) {
        throw InputError(file, "no trajectory samples after the header");
    }
    return SampledTrajectory(std::move(samples));
}

void write_trajectory_csv(const std::filesystem::path& path, const Trajectory& trajectory,
                          double sample_rate_hz) {
    const double start = trajectory.start_time_s(), end = trajectory.end_time_s();
    std::vector<std::string> p;
    if (!(sample_rate_hz > 0.0 && std::isfinite(sample_rate_hz))) {
        p.push_back("sample_rate_hz must be positive (got " + std::to_string(sample_rate_hz) + ")");
    }
    if (!std::isfinite(start) || !std::isfinite(end)) {
        p.push_back("the trajectory has no finite time range");
    } else if (p.empty() && !((end - start) * sample_rate_hz <= 1.0e9)) {
        p.push_back("more than 1e9 samples");
    }
    throw_if_problems("writing trajectory " + path.string(), p);

    constexpr std::size_t kMaxRow = kColumns.size() * 26;
    detail::RowWriter rows(path, kHeader, kMaxRow);
    auto write_row = [&](double t) {
        const Pose pose = trajectory.pose_at(t);
        const RollPitchYaw rpy = to_rpy(pose.attitude);
        const std::array<double, kColumns.size()> v = {t,
                                                       pose.position_m.x,
                                                       pose.position_m.y,
                                                       pose.position_m.z,
                                                       rpy.roll_rad,
                                                       rpy.pitch_rad,
                                                       rpy.yaw_rad};
        char* out = rows.row();
        for (std::size_t c = 0; c < v.size(); ++c) {
            if (c > 0) {
                *out++ = ',';
            }
            out = std::to_chars(out, rows.end(), v[c]).ptr;
        }
        *out++ = '\n';
        rows.end_row(out);
    };
    for (std::uint64_t k = 0;; ++k) {
        const double t = start + static_cast<double>(k) / sample_rate_hz;
        if (t >= end - time_tolerance_s(end)) {
            break;
        }
        write_row(t);
    }
    write_row(end);
    rows.commit();
}

void Trajectory::poses_at(std::span<const double> times_s, std::span<Pose> out) const {
    for (std::size_t i = 0; i < times_s.size(); ++i) {
        out[i] = pose_at(times_s[i]);
    }
}

void LinearLegs::poses_at(std::span<const double> times_s, std::span<Pose> out) const {
#if defined(__x86_64__) && defined(__GNUC__)
    // Without attitudes along the legs (each leg's own), in lanes where the CPU has AVX2.
    if (config_.attitudes.empty() && detail::cpu_simd_level() != detail::SimdLevel::scalar) {
        straight_poses_avx2(times_s_, config_.waypoints_m, attitude_, times_s, out);
        return;
    }
#endif
    poses_at_scalar(times_s, out);
}

void LinearLegs::poses_at_scalar(std::span<const double> times_s, std::span<Pose> out) const {
    const bool turning = !config_.attitudes.empty();  // attitudes slerped along each leg
    LegCursor legs(times_s_);
    Vec3d w0, w1;
    Quat q;
    for (std::size_t i = 0; i < times_s.size(); ++i) {
        bool moved = false;
        const double t = legs.move_to(times_s[i], moved);
        if (moved) {
            w0 = config_.waypoints_m[legs.k];
            w1 = config_.waypoints_m[legs.k + 1];
            q = attitude_[legs.k];
        }
        if (turning) {
            pose_on_leg_into(t, legs.k, out[i]);
            continue;
        }
        // pose_on_leg_into()'s values, stored field by field (a pose returned through memory
        // and copied was read back as 16-byte pieces right after being stored as doubles,
        // which stalls store forwarding).
        const Vec3d p = point_on_leg(leg_fraction(t, legs.t0, legs.t1), w0, w1);
        Pose& pose = out[i];
        pose.position_m.x = p.x;
        pose.position_m.y = p.y;
        pose.position_m.z = p.z;
        pose.attitude.w = q.w;
        pose.attitude.x = q.x;
        pose.attitude.y = q.y;
        pose.attitude.z = q.z;
    }
}

}  // namespace beamtrace
