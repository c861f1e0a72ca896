// A Risley prism pair (Livox Mid-40 / Avia style): two thin wedge prisms on the optical axis,
// each turning at its own rate, deflect the beam along a rosette (a non-repetitive pattern when
// the rates' ratio is not a simple fraction).
//
// Conventions (sensor frame: x forward/optical axis, y left, z up):
// - First-order (thin prism) optics: each prism deviates the beam by delta = (n - 1) alpha
//   (alpha = wedge_deg, n = refractive_index) towards its own orientation theta_k =
//   2 pi frac(rotation_rate_k_hz x i / pulse_rate_hz) (pulse i; theta_k = 0 towards +y, growing
//   towards +z, i.e. right-handed about +x; a negative rate turns the other way). The deviation
//   vector is D = delta (cos theta_1 + cos theta_2, sin theta_1 + sin theta_2) in (y, z).
// - D is applied EXACTLY as a rotation, not as a small-angle offset: the beam makes the angle
//   rho = |D| with sensor +x, in the azimuth psi = atan2(D_z, D_y) about x:
//   direction = [cos rho, sin rho cos psi, sin rho sin psi] (so it is unit length at any rho,
//   and to first order equals [1, D_y, D_z]). The pattern fills a disc of radius 2 delta.
// - With rational rates f_1 = p q0, f_2 = r q0 (p, r coprime integers), the rosette repeats
//   after 1 / q0 seconds (= 1 / gcd(f_1, f_2)).
// - scan_angle_deg = the beam's horizontal angle atan2(d_y, d_x) in degrees (PulseBatch's
//   meaning). One channel (0). Pulse times t_i = start_time_s + i / pulse_rate_hz.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

struct RisleyScannerConfig {
    double pulse_rate_hz = 100'000.0;   ///< pulses per second
    double wedge_deg = 18.8;            ///< apex angle alpha of each prism, in (0, 45)
    double refractive_index = 1.509;    ///< n of the prisms' glass, in (1, 4]
    double rotation_rate_1_hz = 121.6;  ///< first prism, revolutions per second (signed)
    double rotation_rate_2_hz = -77.7;  ///< second prism (negative: counter-rotating)
    double duration_s = 1.0;            ///< survey length; whole pulses only
    double start_time_s = 0.0;          ///< time of pulse 0 (both prisms at theta = 0)

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
    /// delta = (n - 1) alpha, one prism's deviation in radians.
    [[nodiscard]] double prism_deviation_rad() const;
};

class RisleyScanner final : public ScanPattern {
  public:
    using Config = RisleyScannerConfig;

    /// Throws ConfigError listing every problem of `config`.
    explicit RisleyScanner(RisleyScannerConfig config);

    [[nodiscard]] std::uint64_t pulse_count() const override { return pulse_count_; }
    [[nodiscard]] double pulse_rate_hz() const override { return config_.pulse_rate_hz; }
    [[nodiscard]] double start_time_s() const override { return config_.start_time_s; }
    [[nodiscard]] const RisleyScannerConfig& config() const { return config_; }

    /// The deviation vector D = (D_y, D_z) of pulse i, in radians.
    [[nodiscard]] std::pair<double, double> deviation_rad(std::uint64_t i) const;

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;

    RisleyScannerConfig config_;
    std::uint64_t pulse_count_ = 0;
};

}  // namespace beamtrace
