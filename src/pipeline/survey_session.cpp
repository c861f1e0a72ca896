#include "pipeline/detail/survey_session.hpp"

#include <algorithm>
#include <chrono>
#include <string>

#include "beamtrace/core/cancel.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "beamtrace/sensor/leg_sequence.hpp"
#include "pipeline/detail/survey_diagnosis.hpp"
#include "pipeline/detail/survey_materials.hpp"
#include "pipeline/detail/survey_outputs.hpp"
#include "pipeline/detail/survey_reference_range.hpp"

namespace beamtrace::detail {

namespace {

using Clock = std::chrono::steady_clock;

/// Throws ConfigError when the platform does not cover the scanner's time.
void check_platform_covers_scanner(const SurveySpec& spec, const ScanPattern& pattern,
                                   const Trajectory& trajectory) {
    if (pattern.pulse_count() > 0 &&
        !trajectory.covers(pattern.start_time_s(), pattern.end_time_s())) {
        throw ConfigError(spec.source.string() + ": the scanner fires from " +
                          std::to_string(pattern.start_time_s()) + " s to " +
                          std::to_string(pattern.end_time_s()) +
                          " s but the platform moves only from " +
                          std::to_string(trajectory.start_time_s()) + " s to " +
                          std::to_string(trajectory.end_time_s()) + " s");
    }
}

/// The physics line of the LAS provenance: the BRDF and the intensity reference range in use.
std::string physics_provenance(const PhysicsConfig& physics, const ReferenceRange& r) {
    std::string line = "# physics: brdf " + std::string(to_string(physics.brdf)) +
                       ", intensity reference range " + std::to_string(r.reference_range_m) + " m";
    if (r.automatic) {
        line += r.nominal_range_m
                    ? " (auto: half the nominal range " + std::to_string(*r.nominal_range_m) + " m)"
                    : " (auto: the pilot hit nothing)";
    }
    return line + "\n";
}

}  // namespace

SurveySession::SurveySession(const SurveySpec& spec, const SurveyRunConfig& run, ThreadPool& pool)
    : spec_(&spec),
      // Inputs first: nothing is written before the scene, pattern and trajectory are all valid.
      scene_(spec.scene_file.empty() ? make_demo_scene() : load_scene_file(spec.scene_file)),
      pattern_(spec.make_pattern()),
      trajectory_(spec.make_trajectory()) {
    check_platform_covers_scanner(spec, *pattern_, *trajectory_);
    // The survey file's materials are checked before the backend is built.
    std::vector<Material> materials;
    if (spec.physics) {
        materials = survey_materials(scene_, *spec.physics, spec.scene_file);
    }
    // Formats 7 and 8: each point's RGB and NIR from its part's material.
    auto colours = spec.point_format >= 7 ? part_colours(scene_, materials)
                                          : std::vector<std::array<std::uint16_t, 4>>{};
    result_.triangles = scene_.triangle_count();
    result_.spheres = scene_.sphere_count();
    result_.pulses = run.max_pulses > 0 ? std::min(pattern_->pulse_count(), run.max_pulses)
                                        : pattern_->pulse_count();
    const auto t0 = Clock::now();
    // Moving parts leave the backend's geometry: they are traced at each pulse's own time.
    scene_.detach_moving();
    backend_ = make_backend(run.backend, scene_.geometry, pool);
    if (!scene_.moving.empty()) {
        moving_.emplace(scene_.geometry.meshes, scene_.moving, scene_.motions, BvhBuildConfig{},
                        pool, run.backend);
    }
    result_.build_s = std::chrono::duration<double>(Clock::now() - t0).count();

    // Physics (optional): each pulse is sub_rays rays; their hits become the pulse's returns.
    // An `auto` intensity reference range comes from a pilot traced with the same backend.
    std::string provenance_line;
    if (spec.physics) {
        PhysicsConfig config = *spec.physics;
        const ReferenceRange r =
            resolve_reference_range(config, spec, *pattern_, *trajectory_, *backend_, pool);
        result_.intensity_reference_range_m = r.reference_range_m;
        result_.intensity_reference_auto = r.automatic;
        result_.nominal_range_m = r.nominal_range_m;
        provenance_line = physics_provenance(config, r);
        sim_.emplace(std::move(config));
        physics_.emplace(*sim_, scene_, std::move(materials), run.seed);
        max_returns_ = physics_->max_returns();
    }
    throw_if_cancelled(run.cancel, "survey");
    facts_ = survey_sink_facts(spec, run, scene_, *pattern_, *trajectory_, sim_ ? &*sim_ : nullptr,
                               result_.pulses);
    facts_.provenance.insert(facts_.provenance.find('\n') + 1, provenance_line);
    if (!scene_.moving.empty()) {  // the LAS bounds and offset hold the moving parts' paths too
        const Aabb m = scene_.moving_bounds(pattern_->start_time_s(), pattern_->end_time_s());
        facts_.lo_m = min(facts_.lo_m, Vec3d(m.lo) + scene_.origin_m);
        facts_.hi_m = max(facts_.hi_m, Vec3d(m.hi) + scene_.origin_m);
    }
    // The footprint frames preview.png: no pilot without file outputs.
    if (const auto box = run.write_files
                             ? pilot_hit_bounds(spec, *pattern_, *trajectory_, *backend_, pool)
                             : std::nullopt) {
        facts_.footprint_m = {Vec3d(box->lo) + scene_.origin_m, Vec3d(box->hi) + scene_.origin_m};
    }
    source_ = SurveyRaySource{&spec, trajectory_.get(), sim_ ? &*sim_ : nullptr, run.seed};
    sub_rays_ = source_.sub_rays();
    points_ = SurveyPoints{&scene_, sim_.has_value(), sub_rays_, max_returns_, std::move(colours)};
    if (spec.physics && spec.physics->weather) {
        points_.medium_class = spec.physics->weather->medium_class;
    }
    const auto wants = [&](PointAttribute a) {
        return std::find(spec.extra_bytes.begin(), spec.extra_bytes.end(), a) !=
               spec.extra_bytes.end();
    };
    points_.incidence = wants(PointAttribute::incidence_angle);
    points_.instance = wants(PointAttribute::instance_id);
    points_.velocity = wants(PointAttribute::velocity_x) || wants(PointAttribute::velocity_y) ||
                       wants(PointAttribute::velocity_z);
    if (physics_ && moving_) {
        physics_->moving = &*moving_;
    }
    points_.set_sources(spec, *pattern_);  // point source IDs by leg or scanner, channels
    points_.no_echo = run.write_files && std::find(spec.outputs.begin(), spec.outputs.end(),
                                                   "no_echo") != spec.outputs.end();
}

std::size_t SurveySession::blocks() const {
    return static_cast<std::size_t>((result_.pulses + kBlockPulses - 1) / kBlockPulses);
}

void SurveySession::run_block(std::size_t k, BlockWork& w) const {
    const std::uint64_t first = std::uint64_t{k} * kBlockPulses;
    const auto n =
        static_cast<std::size_t>(std::min<std::uint64_t>(kBlockPulses, result_.pulses - first));
    w.size_for(first, n, sub_rays_, max_returns_);
    pattern_->generate(first, n, w.pulses);
    // Without physics the points stage reads each pulse's beam from its ray.
    source_.generate(w.pulses, first, w.rays, 0, sim_ ? w.origin.data() : nullptr,
                     sim_ ? w.axis.data() : nullptr, w.scan_angle.data(), w.scratch);
    // A pulse's sub-rays are a beam (one frustum walk with the BVH): the same hits, bit for bit.
    backend_->intersect_beams(w.rays, 0, n * sub_rays_, sub_rays_, w.hits, w.this_thread);
    if (moving_) {
        trace_moving(w);
    }
    if (physics_) {
        physics_->run(w, *backend_);
    }
    points_.run(w);
}

void SurveySession::trace_moving(BlockWork& w) const {
    const auto& times = w.pulses.time_s;
    const auto [lo, hi] = std::minmax_element(times.begin(), times.begin() + w.pulse_count);
    moving_->prepare(*lo, *hi, w.moving_frame, w.this_thread);
    w.ray_time.resize(w.pulse_count * sub_rays_);
    for (std::size_t k = 0; k < w.pulse_count; ++k) {
        std::fill_n(w.ray_time.begin() + k * sub_rays_, sub_rays_, times[k]);
    }
    moving_->intersect(w.rays, 0, w.ray_time.size(), w.ray_time, w.moving_frame, w.hits);
}

std::vector<std::string> SurveySession::diagnose(std::uint64_t points, ThreadPool& pool) const {
    return diagnose_survey(*spec_, *pattern_, *trajectory_, *backend_, scene_.geometry.bounds(),
                           result_.pulses, points, pool);
}

}  // namespace beamtrace::detail
