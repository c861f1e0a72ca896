// The survey's points stage: each pulse's returns (or, without physics, its one hit) become
// points in world coordinates, labelled with the scene part that was hit.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "beamtrace/scene/scene.hpp"
#include "pipeline/detail/survey_block.hpp"

namespace beamtrace::detail {

struct SurveyPoints {
    const Scene* scene = nullptr;
    bool physics = false;  ///< points from w.returns (else one per hit ray)
    std::size_t sub_rays = 1;
    std::size_t max_returns = 1;
    /// Per scene part: LAS red, green, blue (its material's colour in sRGB, 16 bits) and NIR
    /// (its reflectance); empty: all 0. part_colours() makes it.
    std::vector<std::array<std::uint16_t, 4>> colours;
    /// Fill BlockPoint::incidence_deg (the LAS extra bytes ask for it).
    bool incidence = false;
    /// The LAS class of the weather's points (WeatherConfig::medium_class).
    std::uint8_t medium_class = 7;
    /// output.point_source_id: leg — the first pulse of each leg (LegSequence::first_pulses()),
    /// each point's point source ID its pulse's leg. Empty: the part's id.
    std::vector<std::uint64_t> leg_first_pulse{};
    /// output.point_source_id: leg with `scanners:` (a ScannerSet of LegSequences) — the legs'
    /// start times: a pulse's leg is the last one starting at or before its time.
    std::vector<double> leg_start_s{};
    /// output.point_source_id: scanner — the index of the pulse's scanner (PulseBatch::scanner).
    bool by_scanner = false;
    /// `scanners:` — each scanner's LAS scanner channel, by scanner index; empty: channel 0.
    std::vector<std::uint8_t> scanner_channels{};
    /// Record each pulse without a point in w.points.no_echo (output.no_echo).
    bool no_echo = false;
    /// Fill BlockPoint::instance_id and velocity_mps (the LAS extra bytes ask for them).
    bool instance = false;
    bool velocity = false;

    /// Sets leg_first_pulse, leg_start_s, by_scanner and scanner_channels for the survey's
    /// output.point_source_id and `scanners:` (its pattern: `spec.make_pattern()`).
    void set_sources(const SurveySpec& spec, const ScanPattern& pattern);

    /// Appends the block's points to w.points.points, in pulse order. Thread-safe.
    void run(BlockWork& w) const;

  private:
    /// run() with or without physics, the choice made once a block.
    template <bool Physics>
    void run_pulses(BlockWork& w) const;
    /// run_pulses<false>() when a point needs nothing but its ray, hit and part (no optional
    /// field, no_echo, point source ID by pulse or scanner channel): one pulse in fewer steps.
    void run_hits(BlockWork& w) const;
    /// Whether run_hits() gives run_pulses<false>()'s points: no member above asks for more of
    /// a point than its ray, hit and part (a new optional field must be named here too).
    [[nodiscard]] bool hits_alone() const;
    /// The point source ID of pulse k's points when it is the pulse's (leg or scanner; 0 when
    /// it is the part's).
    [[nodiscard]] std::uint16_t pulse_source_id(const BlockWork& w, std::size_t k) const;
    /// The point of a return the weather's medium made (no part of the scene was hit).
    void medium_point(BlockPoint& p, const PulseReturn& ret) const;
    /// The fields of pulse k's return r that come from the hit part (face, class, point source
    /// ID unless `by_pulse`, incidence, instance, velocity, colour); `last_part`: the part of
    /// the previous hit, updated.
    void part_fields(BlockPoint& p, const BlockWork& w, std::size_t k, std::size_t r,
                     std::uint32_t face, const Vec3d& xyz, bool by_pulse,
                     std::size_t& last_part) const;
    /// The incidence angle of pulse k's return r (physics: of the sample that dominated it;
    /// else of the pulse's ray and the hit face's normal), degrees.
    [[nodiscard]] float incidence_deg(const BlockWork& w, std::size_t k, std::size_t r) const;
};

/// The colours of SurveyPoints::colours for `scene`'s parts: red, green, blue from the part
/// material's linear `color` encoded as sRGB and scaled to 65535, NIR its reflectance x 65535
/// (`materials`: the survey's, resolved at its wavelength; else the scene's).
[[nodiscard]] std::vector<std::array<std::uint16_t, 4>> part_colours(
    const Scene& scene, const std::vector<Material>& materials);

}  // namespace beamtrace::detail
