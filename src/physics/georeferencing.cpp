#include "beamtrace/physics/georeferencing.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace beamtrace {
namespace {

/// The moving-average sum stops where a^K falls below this: its missing variance is < 1e-18.
constexpr double kTruncation = 1e-9;
/// Below this the grid index of a GPS time (~1e9 s) nears 2^63; the process is white by then.
constexpr double kMinCorrelationTime_s = 1e-6;

bool non_negative(double v) {
    return v >= 0 && std::isfinite(v);
}

bool finite(const Vec3d& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void set_axis(Vec3d& v, int axis, double value) {
    (axis == 0 ? v.x : axis == 1 ? v.y : v.z) = value;
}

/// Three white N(0, sigma) draws of pulse `pulse_index` in `stream`.
Vec3d white(double sigma, std::uint64_t seed, std::uint64_t pulse_index, RngStream stream) {
    CounterRng rng(seed, pulse_index, 0, stream);
    const double x = rng.normal(), y = rng.normal(), z = rng.normal();
    return Vec3d{x, y, z} * sigma;
}

/// The random error of every pulse of one kind (position or attitude) into `member` of out[i].
template <typename Member>
void one_kind(double sigma, double tau_s, RngStream white_stream, RngStream gm_stream,
              std::uint64_t seed, std::uint64_t first_pulse, std::span<const double> time_s,
              std::span<PoseError> out, GaussMarkovCache& cache, Member member) {
    if (!(sigma > 0)) {
        return;
    }
    if (!(tau_s > 0)) {
        for (std::size_t i = 0; i < time_s.size(); ++i) {
            out[i].*member = white(sigma, seed, first_pulse + i, white_stream);
        }
        return;
    }
    const GaussMarkovGrid grid(sigma, tau_s, gm_stream);
    if (!time_s.empty()) {
        // Every node the block needs at once (K + span normals instead of K + 2 per pulse),
        // unless the pulses are too sparse on the grid for that range to stay small: then at()
        // evaluates the two nodes of each pulse. Either way each node is the same sum.
        const auto [lo_t, hi_t] = std::minmax_element(time_s.begin(), time_s.end());
        const double lo = std::floor(*lo_t / grid.step_s()), hi = std::floor(*hi_t / grid.step_s());
        if (std::isfinite(lo) && std::isfinite(hi) &&
            hi - lo <= 4.0 * static_cast<double>(time_s.size()) + 1024) {
            grid.fill(seed, static_cast<std::int64_t>(lo), static_cast<std::int64_t>(hi) + 1,
                      cache);
        }
    }
    for (std::size_t i = 0; i < time_s.size(); ++i) {
        out[i].*member = grid.at(seed, time_s[i], cache);
    }
}

}  // namespace

std::vector<std::string> GeoreferencingConfig::validate() const {
    std::vector<std::string> p;
    const auto check = [&](double v, const char* what) {
        if (!non_negative(v)) {
            p.push_back(std::string("noise: ") + what + " must be zero or positive");
        }
    };
    check(position_sigma_m, "position_sigma_m");
    check(attitude_sigma_rad, "attitude_sigma_rad");
    check(correlation_time_s, "correlation_time_s");
    if (correlation_time_s > 0 && correlation_time_s < kMinCorrelationTime_s) {
        p.emplace_back("noise: correlation_time_s must be 0 (white) or at least 1e-6 s");
    }
    if (!finite(lever_arm_error_m)) {
        p.emplace_back("noise: lever_arm_error_m must be finite");
    }
    const RollPitchYaw& b = boresight_error;
    if (!finite(Vec3d{b.roll_rad, b.pitch_rad, b.yaw_rad})) {
        p.emplace_back("noise: boresight_error must be finite");
    }
    return p;
}

bool GeoreferencingConfig::no_random_error() const {
    return position_sigma_m == 0 && attitude_sigma_rad == 0;
}

bool GeoreferencingConfig::none() const {
    const RollPitchYaw& b = boresight_error;
    return no_random_error() && lever_arm_error_m == Vec3d{} && b.roll_rad == 0 &&
           b.pitch_rad == 0 && b.yaw_rad == 0;
}

GaussMarkovGrid::GaussMarkovGrid(double sigma, double tau_s, RngStream stream)
    : sigma_(sigma), h_s_(tau_s / kNodesPerTau), stream_(stream) {
    assert(sigma > 0 && tau_s > 0);
    a_ = std::exp(-h_s_ / tau_s);
    const double scale = sigma_ * std::sqrt(1.0 - a_ * a_);
    // k = 0..K, K the first power with a^K < kTruncation (K = 166 for h = tau / 8).
    for (double ak = 1.0;; ak *= a_) {
        weights_.push_back(scale * ak);
        if (ak < kTruncation) {
            break;
        }
    }
}

void GaussMarkovGrid::fill(std::uint64_t seed, std::int64_t lo, std::int64_t hi,
                           GaussMarkovCache& cache) const {
    assert(hi >= lo);
    const auto count = static_cast<std::size_t>(hi - lo + 1);
    const std::size_t k_max = weights_.size() - 1;
    cache.first_node = lo;
    cache.nodes.assign(count, Vec3d{});
    std::vector<double>& w = cache.w;
    w.resize(count + k_max);
    for (int axis = 0; axis < 3; ++axis) {
        // w[i] is the white normal of node lo - K + i.
        for (std::size_t i = 0; i < w.size(); ++i) {
            const auto m = static_cast<std::uint64_t>(lo - static_cast<std::int64_t>(k_max)) + i;
            w[i] = CounterRng(seed, m, static_cast<std::uint32_t>(axis), stream_).normal();
        }
        for (std::size_t j = 0; j < count; ++j) {
            // x_n = sum_k weights[k] w_{n-k}, k ascending: the same sum for every caller.
            double sum = 0.0;
            for (std::size_t k = 0; k <= k_max; ++k) {
                sum += weights_[k] * w[j + k_max - k];
            }
            set_axis(cache.nodes[j], axis, sum);
        }
    }
}

Vec3d GaussMarkovGrid::node(std::uint64_t seed, std::int64_t n) const {
    GaussMarkovCache cache;
    fill(seed, n, n, cache);
    return cache.nodes[0];
}

Vec3d GaussMarkovGrid::at(std::uint64_t seed, double time_s, GaussMarkovCache& cache) const {
    const double u = time_s / h_s_;
    const double fl = std::floor(u);
    const auto n = static_cast<std::int64_t>(fl);
    const std::int64_t have = static_cast<std::int64_t>(cache.nodes.size());
    if (n < cache.first_node || n + 1 >= cache.first_node + have) {
        fill(seed, n, n + 1, cache);
    }
    const auto i = static_cast<std::size_t>(n - cache.first_node);
    const Vec3d& x0 = cache.nodes[i];
    const Vec3d& x1 = cache.nodes[i + 1];
    const double w1 = u - fl, w0 = 1.0 - w1;
    // Var(w0 x0 + w1 x1) = sigma^2 (w0^2 + w1^2 + 2 w0 w1 a): divide to keep sigma^2.
    const double norm = 1.0 / std::sqrt(w0 * w0 + w1 * w1 + 2.0 * w0 * w1 * a_);
    return (x0 * w0 + x1 * w1) * norm;
}

void platform_errors(const GeoreferencingConfig& config, std::uint64_t seed,
                     std::uint64_t first_pulse, std::span<const double> time_s,
                     std::span<PoseError> out, PlatformErrorScratch& scratch) {
    assert(out.size() == time_s.size());
    std::fill(out.begin(), out.end(), PoseError{});
    one_kind(config.position_sigma_m, config.correlation_time_s, RngStream::position_noise,
             RngStream::gauss_markov_position, seed, first_pulse, time_s, out, scratch.position,
             &PoseError::position_m);
    one_kind(config.attitude_sigma_rad, config.correlation_time_s, RngStream::attitude_noise,
             RngStream::gauss_markov_attitude, seed, first_pulse, time_s, out, scratch.attitude,
             &PoseError::attitude_rad);
}

Pose measured_platform_pose(const Pose& platform, const PoseError& e) {
    Pose out{platform.position_m + e.position_m, platform.attitude};
    const double angle = length(e.attitude_rad);
    if (angle > 0) {
        // A body-frame error: applied before the attitude.
        out.attitude =
            (platform.attitude * Quat::from_axis_angle(e.attitude_rad * (1.0 / angle), angle))
                .normalized();
    }
    return out;
}

Pose measured_mount(const GeoreferencingConfig& config, const Pose& mount) {
    Pose out{mount.position_m + config.lever_arm_error_m, mount.attitude};
    const RollPitchYaw& b = config.boresight_error;
    if (b.roll_rad != 0 || b.pitch_rad != 0 || b.yaw_rad != 0) {
        out.attitude = (mount.attitude * Quat::from_rpy(b)).normalized();
    }
    return out;
}

Pose measured_sensor_pose(const GeoreferencingConfig& config, const Pose& platform,
                          const Pose& mount, const PoseError& e) {
    return measured_platform_pose(platform, e) * measured_mount(config, mount);
}

}  // namespace beamtrace
