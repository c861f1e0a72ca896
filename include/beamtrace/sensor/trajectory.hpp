// Platforms and trajectories: the pose of a platform over time, and of a sensor mounted on it.
//
// Conventions:
// - A Pose maps platform coordinates to the world: world = position_m + attitude.rotate(p).
//   Attitudes given as [roll pitch yaw] use the report's convention (Quat::from_rpy): a
//   platform-frame direction d goes to the world as d * (Rx(roll) Ry(pitch) Rz(yaw)). With zero
//   roll and pitch, yaw = psi turns the platform's +x axis to the world direction
//   [cos psi, -sin psi, 0]: positive yaw turns CLOCKWISE seen from above (from +x towards -y).
//   Pitch -pi/2 turns +x straight down.
// - Times are seconds in one time base shared with the scan pattern (e.g. GPS time).
// - Outside [start_time_s(), end_time_s()] the moving trajectories THROW ConfigError (a survey
//   longer than its trajectory is a configuration mistake that clamping would hide as a
//   platform standing still); times within 1e-9 s (relative to |t|, at least 1e-9 s) of an end
//   are clamped to it, to absorb rounding in pulse times.
#pragma once

#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/quat.hpp"
#include "beamtrace/core/rotation.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

class Trajectory {
  public:
    virtual ~Trajectory() = default;
    Trajectory() = default;
    Trajectory(const Trajectory&) = default;
    Trajectory& operator=(const Trajectory&) = default;
    Trajectory(Trajectory&&) = default;
    Trajectory& operator=(Trajectory&&) = default;

    /// The platform-to-world pose at `time_s`; throws ConfigError outside the time range.
    [[nodiscard]] virtual Pose pose_at(double time_s) const = 0;
    /// out[i] = pose_at(times_s[i]) (the same values), one virtual call for the whole batch.
    /// `out` must have times_s.size() elements.
    virtual void poses_at(std::span<const double> times_s, std::span<Pose> out) const;
    [[nodiscard]] virtual double start_time_s() const = 0;
    [[nodiscard]] virtual double end_time_s() const = 0;

    /// True when [first_s, last_s] lies within the time range (the same tolerance as pose_at).
    [[nodiscard]] bool covers(double first_s, double last_s) const;
};

/// A platform that never moves. Its time range is (-inf, +inf) unless given.
class StaticPlatform final : public Trajectory {
  public:
    explicit StaticPlatform(Pose pose,
                            double start_time_s = -std::numeric_limits<double>::infinity(),
                            double end_time_s = std::numeric_limits<double>::infinity());
    [[nodiscard]] Pose pose_at(double time_s) const override;
    [[nodiscard]] double start_time_s() const override { return start_; }
    [[nodiscard]] double end_time_s() const override { return end_; }

  private:
    Pose pose_;
    double start_, end_;
};

struct LinearLegsConfig {
    /// Polyline corners in world metres; at least 2, consecutive ones distinct.
    std::vector<Vec3d> waypoints_m;
    /// Empty: the platform faces along each leg (yaw from the leg's horizontal direction,
    /// yaw = atan2(-dy, dx) in the report's convention, zero roll and pitch), so a sensor with an
    /// identity mount looks along the leg; a vertical leg keeps the previous leg's heading (the
    /// next leg's for a first leg, 0 if all are vertical). Otherwise one attitude per waypoint
    /// (radians, the report's convention), slerped along each leg.
    std::vector<RollPitchYaw> attitudes;
    double speed_mps = 50.0;    ///< constant speed along the (3-D) polyline
    double start_time_s = 0.0;  ///< time at the first waypoint

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// Waypoints flown at constant speed: position linear along each leg, time at waypoint k =
/// start_time_s + (path length to k) / speed_mps. With attitudes facing along the legs the
/// heading changes instantly at a waypoint; at the waypoint's exact time the pose is that of
/// the leg that starts there.
class LinearLegs final : public Trajectory {
  public:
    /// Throws ConfigError listing every problem of `config`.
    explicit LinearLegs(LinearLegsConfig config);
    [[nodiscard]] Pose pose_at(double time_s) const override;
    void poses_at(std::span<const double> times_s, std::span<Pose> out) const override;
    /// poses_at() one pose at a time, without SIMD lanes: what a CPU without AVX2 runs (the
    /// same poses, bit for bit; tests compare the two).
    void poses_at_scalar(std::span<const double> times_s, std::span<Pose> out) const;
    [[nodiscard]] double start_time_s() const override { return times_s_.front(); }
    [[nodiscard]] double end_time_s() const override { return times_s_.back(); }
    /// Time at each waypoint.
    [[nodiscard]] const std::vector<double>& waypoint_times_s() const { return times_s_; }

  private:
    /// The pose at time t (within the range) on leg k (times_s_[k] <= t <= times_s_[k + 1]).
    [[nodiscard]] Pose pose_on_leg(double t, std::size_t k) const;
    /// pose_on_leg into `out` (poses_at: no pose returned through memory and copied).
    void pose_on_leg_into(double t, std::size_t k, Pose& out) const;
    LinearLegsConfig config_;
    std::vector<double> times_s_;
    std::vector<Quat> attitude_;  ///< per waypoint (given) or per leg (facing along it)
};

/// One row of a sampled trajectory.
struct TrajectorySample {
    double time_s = 0.0;
    Vec3d position_m;
    RollPitchYaw attitude;  ///< radians, the report's convention
};

/// Timestamped poses: linear position and slerped attitude between samples, exact at them.
class SampledTrajectory final : public Trajectory {
  public:
    /// Throws ConfigError naming the row (0-based) of a non-finite value or a time not after
    /// the previous one, and for an empty list. A single sample is a valid (instant) range.
    explicit SampledTrajectory(std::vector<TrajectorySample> samples);
    [[nodiscard]] Pose pose_at(double time_s) const override;
    [[nodiscard]] double start_time_s() const override { return samples_.front().time_s; }
    [[nodiscard]] double end_time_s() const override { return samples_.back().time_s; }
    [[nodiscard]] const std::vector<TrajectorySample>& samples() const { return samples_; }

  private:
    std::vector<TrajectorySample> samples_;
    std::vector<Quat> attitude_;
};

/// The inverse of Quat::from_rpy: roll and yaw in (-pi, pi], pitch in [-pi/2, pi/2]. At
/// pitch +-pi/2 (gimbal lock) roll is 0 and yaw carries the whole rotation about z.
[[nodiscard]] RollPitchYaw to_rpy(const Quat& attitude);

/// Reads a trajectory CSV: the header `time_s,x,y,z,roll,pitch,yaw` (spaces around fields
/// allowed), then one sample per line (metres, radians in the report's convention, times
/// strictly increasing). Blank lines and lines starting with '#' are skipped; CRLF accepted.
/// Throws InputError naming the file and line for a missing or wrong header, a wrong field
/// count, a malformed or non-finite number or a time not after the previous row's; naming the
/// file when it cannot be read or holds no samples.
[[nodiscard]] SampledTrajectory read_trajectory_csv(const std::filesystem::path& path);

/// Samples `trajectory` at start + k / sample_rate_hz for k = 0, 1, ... while before the end,
/// plus the end time itself, and writes them as a trajectory CSV (shortest round-trip numbers)
/// through AtomicFile. Throws ConfigError for a non-positive rate or an infinite time range,
/// OutputError when the file cannot be written.
void write_trajectory_csv(const std::filesystem::path& path, const Trajectory& trajectory,
                          double sample_rate_hz);

/// Where a sensor sits on its platform: sensor-to-platform pose, i.e. the lever arm (the
/// sensor's origin in platform metres) and the boresight attitude.
struct Mount {
    Pose sensor_to_platform;

    /// A mount from a lever arm and a boresight in the report's [roll pitch yaw] (radians).
    /// E.g. {0, -pi/2, 0} points the sensor's +x straight down from a level platform.
    [[nodiscard]] static Mount from_lever_arm(const Vec3d& lever_arm_m,
                                              const RollPitchYaw& boresight = {}) {
        return {{lever_arm_m, Quat::from_rpy(boresight)}};
    }
};

/// The sensor-to-world pose at `time_s`: platform pose x mount.
[[nodiscard]] inline Pose sensor_pose(const Trajectory& trajectory, const Mount& mount,
                                      double time_s) {
    return trajectory.pose_at(time_s) * mount.sensor_to_platform;
}

}  // namespace beamtrace
