// Counter-based random numbers (Philox-4x32-10, Salmon et al., SC'11 "Parallel random numbers:
// as easy as 1, 2, 3"). A draw is a pure function of (seed, pulse index, sub-ray index, stream,
// draw number): results never depend on threads, chunking or the order pulses are processed in.
//
// Layout: the 64-bit key is the seed; the 128-bit counter is
//   [draw block (32 bits), sub-ray (32 bits), pulse index low, pulse index high] with the stream
//   folded into the key's high word, so every (pulse, sub-ray, stream) gets its own sequence of
//   2^32 blocks of four 32-bit words.
// Usage:
//   CounterRng rng(seed, pulse_index, sub_ray, RngStream::range_noise);
//   const double g = rng.normal();   // N(0, 1)
//   const double u = rng.uniform();  // [0, 1)
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace beamtrace {

/// Independent streams, one per use, so adding a use never shifts another's numbers.
enum class RngStream : std::uint32_t {
    range_noise = 1,
    angle_jitter = 2,
    position_noise = 3,
    attitude_noise = 4,
    dropout = 5,
    waveform_noise = 6,
    gauss_markov_position = 7,  ///< white input of the position Gauss-Markov grid (per node)
    gauss_markov_attitude = 8,  ///< white input of the attitude Gauss-Markov grid (per node)
    weather_particles = 9,      ///< rain and snow particles drawn in a beam cell (per sub-ray)
    user = 1000,                ///< first value free for callers outside the physics module
};

/// One Philox-4x32-10 block: four 32-bit words from a 128-bit counter and a 64-bit key.
[[nodiscard]] constexpr std::array<std::uint32_t, 4> philox4x32(std::array<std::uint32_t, 4> ctr,
                                                                std::array<std::uint32_t, 2> key) {
    constexpr std::uint32_t kMul0 = 0xD2511F53u, kMul1 = 0xCD9E8D57u;
    constexpr std::uint32_t kWeyl0 = 0x9E3779B9u, kWeyl1 = 0xBB67AE85u;
    for (int round = 0; round < 10; ++round) {
        const std::uint64_t p0 = std::uint64_t{kMul0} * ctr[0];
        const std::uint64_t p1 = std::uint64_t{kMul1} * ctr[2];
        const auto hi0 = static_cast<std::uint32_t>(p0 >> 32), lo0 = static_cast<std::uint32_t>(p0);
        const auto hi1 = static_cast<std::uint32_t>(p1 >> 32), lo1 = static_cast<std::uint32_t>(p1);
        ctr = {hi1 ^ ctr[1] ^ key[0], lo1, hi0 ^ ctr[3] ^ key[1], lo0};
        key[0] += kWeyl0;
        key[1] += kWeyl1;
    }
    return ctr;
}

/// A stream of uniform and normal numbers for one (seed, pulse, sub-ray, stream). Cheap to
/// construct (no state but the counter): make one where it is needed, never share one.
class CounterRng {
  public:
    CounterRng(std::uint64_t seed, std::uint64_t pulse_index, std::uint32_t sub_ray,
               RngStream stream)
        : key_{static_cast<std::uint32_t>(seed),
               static_cast<std::uint32_t>(seed >> 32) ^
                   (static_cast<std::uint32_t>(stream) * 0x85EBCA6Bu)},
          ctr_{0, sub_ray, static_cast<std::uint32_t>(pulse_index),
               static_cast<std::uint32_t>(pulse_index >> 32)} {}

    /// The next 32 random bits.
    [[nodiscard]] std::uint32_t next_u32() {
        if (used_ == 4) {
            block_ = philox4x32(ctr_, key_);
            ++ctr_[0];
            used_ = 0;
        }
        return block_[used_++];
    }

    /// Uniform in [0, 1) with 53 random bits.
    [[nodiscard]] double uniform() {
        const std::uint64_t hi = next_u32() >> 5;  // 27 bits
        const std::uint64_t lo = next_u32() >> 6;  // 26 bits
        return static_cast<double>((hi << 26) | lo) * 0x1.0p-53;
    }

    /// Uniform in (0, 1]: safe for log().
    [[nodiscard]] double uniform_open() { return 1.0 - uniform(); }

    /// Standard normal N(0, 1) by Box-Muller; the second value of each pair is kept for the next
    /// call, so the sequence is still a pure function of the constructor's arguments.
    [[nodiscard]] double normal() {
        if (has_spare_) {
            has_spare_ = false;
            return spare_;
        }
        const double r = std::sqrt(-2.0 * std::log(uniform_open()));
        const double phi = 2.0 * std::numbers::pi * uniform();
        spare_ = r * std::sin(phi);
        has_spare_ = true;
        return r * std::cos(phi);
    }

  private:
    std::array<std::uint32_t, 2> key_;
    std::array<std::uint32_t, 4> ctr_;
    std::array<std::uint32_t, 4> block_{};
    int used_ = 4;
    double spare_ = 0.0;
    bool has_spare_ = false;
};

}  // namespace beamtrace
