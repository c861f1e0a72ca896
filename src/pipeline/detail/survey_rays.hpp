// The rays of a survey's pulses, exactly as run_survey traces them: the platform's pose at each
// pulse's time, the mount, the physics' sub-ray pattern; and the beam each pulse reports, placed
// with the MEASURED pose (the physics' georeferencing errors, physics/georeferencing.hpp). Shared
// by run_survey and the throughput benchmark (which traces the same rays with raw Embree).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/physics/georeferencing.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/pipeline/survey.hpp"

namespace beamtrace::detail {

/// The LAS 1.4 scan angle of a world direction: the rotation from straight down about the
/// platform's direction of travel, counter-clockwise seen from behind (so positive to the right),
/// in degrees, clamped to [-90, 90].
[[nodiscard]] float las_scan_angle_deg(const Vec3d& dir, const Vec3d& forward);
/// las_scan_angle_deg() of the directions of rays [first, first + count) into out[0, count):
/// the same floats, computed a batch at a time (vectorized).
void las_scan_angles_deg(const RayBatch& rays, std::size_t first, std::size_t count,
                         const Vec3d& forward, float* out);

struct SurveyRaySource {
    const SurveySpec* spec = nullptr;
    const Trajectory* trajectory = nullptr;
    const PulseSimulator* sim = nullptr;  ///< null: one ray per pulse, no pose errors
    std::uint64_t seed = 1;
    /// Without physics, four pulses at a time with AVX2 where the CPU has it (false: one at a
    /// time; the same rays, bit for bit).
    bool lanes = true;

    [[nodiscard]] std::size_t sub_rays() const { return sim ? sim->sub_ray_count() : 1; }

    /// Working space of generate(), reused from call to call.
    struct Scratch {
        std::vector<Vec3d> dirs;
        std::vector<Vec3d> origins;  ///< the sub-rays' start points (exit pupil)
        std::vector<Pose> platform;
        std::vector<PoseError> errors;
        PlatformErrorScratch georeferencing;
    };

    /// Rays of pulses[i] (global pulse index first + i) into rays[ray_offset + i * sub_rays(),
    /// ... + sub_rays()), traced from the TRUE sensor pose; each pulse's origin, beam axis and
    /// LAS scan angle as the system MEASURES them (the pose with the georeferencing errors: the
    /// points go at origin + axis * range) into origin[i], axis[i], scan_angle[i]. Without
    /// errors (or without physics) origin/axis are the ray's; without physics they may be null (the
    /// rays are the beams). `rays` must be large enough.
    void generate(const PulseBatch& pulses, std::uint64_t first, RayBatch& rays,
                  std::size_t ray_offset, Vec3d* origin, Vec3d* axis, float* scan_angle,
                  Scratch& scratch) const;

  private:
    /// generate() without physics for `scanners:`: each pulse's scanner's mount and range gate.
    void generate_scanners(const PulseBatch& pulses, RayBatch& rays, std::size_t ray_offset,
                           Vec3d* origin, Vec3d* axis, float* scan_angle, Scratch& scratch) const;
    /// generate() with physics: sub-rays, jitter and the measured beam.
    void generate_physics(const PulseBatch& pulses, std::uint64_t first, RayBatch& rays,
                          std::size_t ray_offset, Vec3d* origin, Vec3d* axis, float* scan_angle,
                          Scratch& scratch) const;
};

}  // namespace beamtrace::detail
