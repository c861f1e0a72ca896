#include "pipeline/detail/survey_reference_range.hpp"

#include <algorithm>
#include <vector>

#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "pipeline/detail/survey_rays.hpp"

namespace beamtrace::detail {

RayBatch pilot_rays(const SurveySpec& spec, const ScanPattern& pattern,
                    const Trajectory& trajectory, std::size_t max_pulses) {
    const std::uint64_t total = pattern.pulse_count();
    const auto k_count = static_cast<std::size_t>(std::min<std::uint64_t>(max_pulses, total));
    // The pilot's pulses, one at a time (they are far apart), into one batch.
    PulseBatch pulses, one;
    pulses.resize(k_count);
    for (std::size_t k = 0; k < k_count; ++k) {
        const std::uint64_t index =
            (2 * std::uint64_t{k} + 1) * total / (2 * std::uint64_t{k_count});
        pattern.generate(index, 1, one);
        pulses.time_s[k] = one.time_s[0];
        pulses.direction[k] = one.direction[0];
        pulses.channel[k] = one.channel[0];
        pulses.scan_angle_deg[k] = one.scan_angle_deg[0];
        pulses.scanner[k] = one.scanner[0];
    }
    // No simulator: ideal single rays along the beam axes, no noise.
    const SurveyRaySource source{&spec, &trajectory, nullptr, 1};
    RayBatch rays;
    rays.resize(k_count);
    std::vector<Vec3d> origin(k_count), axis(k_count);
    std::vector<float> scan_angle(k_count);
    SurveyRaySource::Scratch scratch;
    source.generate(pulses, 0, rays, 0, origin.data(), axis.data(), scan_angle.data(), scratch);
    return rays;
}

std::optional<Aabb> pilot_hit_bounds(const SurveySpec& spec, const ScanPattern& pattern,
                                     const Trajectory& trajectory, const Backend& backend,
                                     ThreadPool& pool) {
    const RayBatch rays = pilot_rays(spec, pattern, trajectory);
    HitBatch hits;
    hits.resize(rays.size());
    backend.intersect(rays, 0, rays.size(), hits, pool);
    Aabb box;
    bool any = false;
    for (std::size_t k = 0; k < rays.size(); ++k) {
        if (hits.hit(k)) {
            const double t = hits.t[k];
            box.extend(Vec3f(Vec3d{rays.ox[k] + rays.dx[k] * t, rays.oy[k] + rays.dy[k] * t,
                                   rays.oz[k] + rays.dz[k] * t}));
            any = true;
        }
    }
    if (!any) {
        return std::nullopt;
    }
    const Vec3f grow = (box.hi - box.lo) * 0.1f + Vec3f{1e-3f, 1e-3f, 1e-3f};
    box.lo = box.lo - grow;
    box.hi = box.hi + grow;
    return box;
}

std::optional<double> survey_nominal_range_m(const SurveySpec& spec, const ScanPattern& pattern,
                                             const Trajectory& trajectory, const Backend& backend,
                                             ThreadPool& pool) {
    const RayBatch rays = pilot_rays(spec, pattern, trajectory);
    const std::size_t k_count = rays.size();
    if (k_count == 0) {
        return std::nullopt;
    }
    HitBatch hits;
    hits.resize(k_count);
    backend.intersect(rays, 0, k_count, hits, pool);
    std::vector<double> ranges;
    for (std::size_t k = 0; k < k_count; ++k) {
        if (hits.hit(k)) {
            ranges.push_back(hits.t[k]);
        }
    }
    if (ranges.empty()) {
        return std::nullopt;
    }
    const auto mid = ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2);
    std::nth_element(ranges.begin(), mid, ranges.end());
    return *mid;
}

ReferenceRange resolve_reference_range(PhysicsConfig& physics, const SurveySpec& spec,
                                       const ScanPattern& pattern, const Trajectory& trajectory,
                                       const Backend& backend, ThreadPool& pool) {
    ReferenceRange out;
    std::optional<double>& r_ref = physics.radiometry.intensity_reference_range_m;
    if (!r_ref) {
        out.automatic = true;
        out.nominal_range_m = survey_nominal_range_m(spec, pattern, trajectory, backend, pool);
        r_ref = out.nominal_range_m && *out.nominal_range_m > 0
                    ? kReferenceRangeFraction * *out.nominal_range_m
                    : kDefaultIntensityReferenceRange_m;
    }
    out.reference_range_m = *r_ref;
    return out;
}

}  // namespace beamtrace::detail
