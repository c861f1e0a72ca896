// `beamtrace survey`: the stages (poses and rays, trace, physics, points) of each block of
// pulses on the pool threads, the sinks' encoding beside them, the sinks' writes in block order
// on one writer thread (docs/dev/architecture-pipeline.md).
#include <algorithm>
#include <chrono>
#include <optional>
#include <system_error>

#include "beamtrace/core/cancel.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "core/created_dirs.hpp"
#include "pipeline/detail/ordered_blocks.hpp"
#include "pipeline/detail/survey_block.hpp"
#include "pipeline/detail/survey_diagnosis.hpp"
#include "pipeline/detail/survey_materials.hpp"
#include "pipeline/detail/survey_outputs.hpp"
#include "pipeline/detail/survey_physics.hpp"
#include "pipeline/detail/survey_points.hpp"
#include "pipeline/detail/survey_rays.hpp"
#include "pipeline/detail/survey_reference_range.hpp"

namespace beamtrace {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// What a survey reads before anything is written: the scene, the pattern, the trajectory.
struct SurveyInputs {
    Scene scene;
    std::unique_ptr<ScanPattern> pattern;
    std::unique_ptr<Trajectory> trajectory;
};

/// Loads the inputs; throws ConfigError when the platform does not cover the scanner's time.
SurveyInputs load_survey_inputs(const SurveySpec& spec) {
    SurveyInputs in{spec.scene_file.empty() ? make_demo_scene() : load_scene_file(spec.scene_file),
                    spec.make_pattern(), spec.make_trajectory()};
    const ScanPattern& pattern = *in.pattern;
    const Trajectory& trajectory = *in.trajectory;
    if (pattern.pulse_count() > 0 &&
        !trajectory.covers(pattern.start_time_s(), pattern.end_time_s())) {
        throw ConfigError(spec.source.string() + ": the scanner fires from " +
                          std::to_string(pattern.start_time_s()) + " s to " +
                          std::to_string(pattern.end_time_s()) +
                          " s but the platform moves only from " +
                          std::to_string(trajectory.start_time_s()) + " s to " +
                          std::to_string(trajectory.end_time_s()) + " s");
    }
    return in;
}

/// The physics line of the LAS provenance: the BRDF and the intensity reference range in use.
std::string physics_provenance(const PhysicsConfig& physics, const detail::ReferenceRange& r) {
    std::string line = "# physics: brdf " + std::string(to_string(physics.brdf)) +
                       ", intensity reference range " + std::to_string(r.reference_range_m) + " m";
    if (r.automatic) {
        line += r.nominal_range_m
                    ? " (auto: half the nominal range " + std::to_string(*r.nominal_range_m) + " m)"
                    : " (auto: the pilot hit nothing)";
    }
    return line + "\n";
}

void create_output_dir(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) {
        throw OutputError(dir.string() + ": cannot create output directory" +
                          (ec ? ": " + ec.message() : std::string()));
    }
}

/// The physics of a run: the pulse simulator and its stage, and the provenance line.
struct RunPhysics {
    RunPhysics() = default;
    RunPhysics(const RunPhysics&) = delete;  // nor moved: physics points into sim
    RunPhysics& operator=(const RunPhysics&) = delete;

    std::optional<PulseSimulator> sim;
    std::optional<detail::SurveyPhysics> physics;  ///< refers to *sim
    std::string provenance_line;
};

/// Sets up spec.physics: each pulse is sub_rays rays, whose hits become the pulse's returns. An
/// `auto` intensity reference range comes from a pilot traced with the same backend; the range
/// in use goes into `result`.
void set_up_physics(RunPhysics& out, const SurveySpec& spec, const SurveyInputs& in,
                    std::vector<Material> materials, const Backend& backend, ThreadPool& pool,
                    std::uint64_t seed, SurveyResult& result) {
    PhysicsConfig config = *spec.physics;
    const detail::ReferenceRange r =
        detail::resolve_reference_range(config, spec, *in.pattern, *in.trajectory, backend, pool);
    result.intensity_reference_range_m = r.reference_range_m;
    result.intensity_reference_auto = r.automatic;
    result.nominal_range_m = r.nominal_range_m;
    out.provenance_line = physics_provenance(config, r);
    out.sim.emplace(std::move(config));
    out.physics.emplace(*out.sim, in.scene, std::move(materials), seed);
}

/// What the run's sinks are told: survey_sink_facts, the physics line of the provenance, and
/// (with file outputs: it frames preview.png) the footprint of the pilot's hits.
SinkFacts run_sink_facts(const SurveySpec& spec, const SurveyRunConfig& run, const SurveyInputs& in,
                         const PulseSimulator* sim, const std::string& provenance_line,
                         const Backend& backend, ThreadPool& pool, std::uint64_t pulses) {
    SinkFacts facts =
        detail::survey_sink_facts(spec, run, in.scene, *in.pattern, *in.trajectory, sim, pulses);
    facts.provenance.insert(facts.provenance.find('\n') + 1, provenance_line);
    if (!run.write_files) {
        return facts;
    }
    if (const auto box =
            detail::pilot_hit_bounds(spec, *in.pattern, *in.trajectory, backend, pool)) {
        facts.footprint_m = {Vec3d(box->lo) + in.scene.origin_m,
                             Vec3d(box->hi) + in.scene.origin_m};
    }
    return facts;
}

/// The stages one block of pulses goes through on one pool thread: poses and rays, trace,
/// physics, points, and the sinks' encoding.
struct BlockStages {
    const ScanPattern* pattern = nullptr;
    const detail::SurveyRaySource* rays = nullptr;
    const Backend* backend = nullptr;
    const detail::SurveyPhysics* physics = nullptr;  ///< null: ideal single rays
    detail::SurveyPoints points;
    const detail::SinkSet* sinks = nullptr;
    std::uint64_t pulses = 0;  ///< pulses of the survey
    std::size_t sub_rays = 1, max_returns = 1;

    void run(std::size_t block_index, detail::BlockWork& w, detail::BlockOutput& out) const {
        const std::uint64_t first = std::uint64_t{block_index} * detail::kBlockPulses;
        const auto n =
            static_cast<std::size_t>(std::min<std::uint64_t>(detail::kBlockPulses, pulses - first));
        w.size_for(first, n, sub_rays, max_returns);
        pattern->generate(first, n, w.pulses);
        rays->generate(w.pulses, first, w.rays, 0, w.origin.data(), w.axis.data(),
                       w.scan_angle.data(), w.scratch);
        backend->intersect(w.rays, 0, n * sub_rays, w.hits, w.this_thread);
        if (physics != nullptr) {
            physics->run(w);
        }
        points.run(w);
        sinks->encode(w.points, out);
    }
};

/// Runs every block through `stages` on the pool and writes them to `sinks` in block order,
/// with at most `window` blocks in flight; returns the number of points written. Checks `cancel`
/// before each block is taken and written: Interrupted stops every thread.
std::uint64_t stream_blocks(const BlockStages& stages, detail::SinkSet& sinks, std::size_t window,
                            ThreadPool& pool, const ProgressFn& progress,
                            const CancelToken* cancel) {
    const std::uint64_t pulses = stages.pulses;
    const auto blocks =
        static_cast<std::size_t>((pulses + detail::kBlockPulses - 1) / detail::kBlockPulses);
    const std::size_t progress_every = std::max<std::size_t>(1, window / 4);
    std::uint64_t points = 0;
    detail::OrderedBlocks ordered(blocks, window, [&](std::size_t k, detail::BlockOutput& out) {
        throw_if_cancelled(cancel, "survey");  // on the writer: finish() rethrows it
        sinks.write(out);
        points += out.points;
        if (progress && ((k + 1) % progress_every == 0 || k + 1 == blocks)) {
            progress(static_cast<std::size_t>(
                         std::min<std::uint64_t>((k + 1) * detail::kBlockPulses, pulses)),
                     static_cast<std::size_t>(pulses));
        }
    });
    if (progress) {
        progress(
            0, static_cast<std::size_t>(pulses));  // the survey stage starts: rates count from here
    }
    detail::WorkShelf shelf;
    pool.parallel_for(blocks, 1, [&](std::size_t kb, std::size_t ke) {
        for (std::size_t k = kb; k < ke; ++k) {
            if (cancel != nullptr && cancel->requested()) {
                ordered.abort();
                throw_if_cancelled(cancel, "survey");
            }
            detail::BlockOutput* out = ordered.acquire(k);
            if (out == nullptr) {
                return;  // the writer failed, or another block did: finish() or parallel_for says
            }
            try {
                std::unique_ptr<detail::BlockWork> work = shelf.take();
                stages.run(k, *work, *out);
                shelf.put(std::move(work));
            } catch (...) {
                ordered.abort();
                throw;
            }
            ordered.publish(k);
        }
    });
    ordered.finish();
    return points;
}

}  // namespace

std::unique_ptr<ScanPattern> SurveySpec::make_pattern() const {
    return scanner.make_pattern();
}

std::unique_ptr<Trajectory> SurveySpec::make_trajectory() const {
    switch (platform) {
        case PlatformKind::fixed:
            return std::make_unique<StaticPlatform>(fixed_pose);
        case PlatformKind::legs:
            return std::make_unique<LinearLegs>(legs);
        case PlatformKind::trajectory:
            return std::make_unique<SampledTrajectory>(read_trajectory_csv(trajectory_file));
    }
    throw ConfigError("unknown platform kind");
}

RayBatch survey_rays(const SurveySpec& spec, std::uint64_t seed, std::uint64_t max_pulses,
                     ThreadPool& pool) {
    const auto pattern = spec.make_pattern();
    const auto trajectory = spec.make_trajectory();
    std::optional<PulseSimulator> sim;
    if (spec.physics) {
        sim.emplace(*spec.physics);
    }
    const detail::SurveyRaySource source{&spec, trajectory.get(), sim ? &*sim : nullptr, seed};
    const std::uint64_t pulses =
        max_pulses > 0 ? std::min(pattern->pulse_count(), max_pulses) : pattern->pulse_count();
    const std::size_t sub_rays = source.sub_rays();
    RayBatch rays;
    rays.resize(static_cast<std::size_t>(pulses) * sub_rays);
    std::vector<Vec3d> origin(static_cast<std::size_t>(pulses)), axis(origin.size());
    std::vector<float> scan_angle(origin.size());
    pool.parallel_for(origin.size(), detail::kBlockPulses, [&](std::size_t b, std::size_t e) {
        PulseBatch batch;
        detail::SurveyRaySource::Scratch scratch;
        pattern->generate(b, e - b, batch);
        source.generate(batch, b, rays, b * sub_rays, origin.data() + b, axis.data() + b,
                        scan_angle.data() + b, scratch);
    });
    return rays;
}

SurveyResult run_survey(const SurveySpec& spec, const SurveyRunConfig& run,
                        const ProgressFn& progress) {
    if (run.write_files && run.output_dir.empty()) {
        throw ConfigError("no output directory");
    }
    throw_if_cancelled(run.cancel, "survey");
    SurveyResult result;
    ThreadPool pool(run.threads);
    // Inputs first: nothing is written before the scene, pattern and trajectory are all valid.
    const SurveyInputs in = load_survey_inputs(spec);
    // The survey file's materials are checked before the backend is built.
    std::vector<Material> materials;
    if (spec.physics) {
        materials = detail::survey_materials(in.scene, *spec.physics, spec.scene_file);
    }
    // Formats 7 and 8: each point's RGB and NIR from its part's material.
    const auto colours = spec.point_format >= 7 ? detail::part_colours(in.scene, materials)
                                                : std::vector<std::array<std::uint16_t, 4>>{};
    result.triangles = in.scene.triangle_count();
    result.spheres = in.scene.sphere_count();
    result.pulses = run.max_pulses > 0 ? std::min(in.pattern->pulse_count(), run.max_pulses)
                                       : in.pattern->pulse_count();

    auto t0 = Clock::now();
    const auto backend = make_backend(run.backend, in.scene.geometry, pool);
    result.build_s = seconds_since(t0);

    RunPhysics phys;  // stays in place: phys.physics refers to phys.sim
    if (spec.physics) {
        set_up_physics(phys, spec, in, std::move(materials), *backend, pool, run.seed, result);
    }
    const PulseSimulator* sim = phys.sim ? &*phys.sim : nullptr;
    const auto& physics = phys.physics;

    throw_if_cancelled(run.cancel, "survey");
    // Declared before the sinks: on an error or interrupt the sinks remove their temporaries
    // first, then the folders this run created go if empty.
    std::optional<CreatedDirs> created;
    if (run.write_files) {
        created.emplace(run.output_dir);
        create_output_dir(run.output_dir);
    }
    detail::SinkSet sinks = detail::open_run_sinks(
        spec, run,
        run_sink_facts(spec, run, in, sim, phys.provenance_line, *backend, pool, result.pulses));
    t0 = Clock::now();
    const detail::SurveyRaySource source{&spec, in.trajectory.get(), sim, run.seed};
    BlockStages stages{in.pattern.get(),
                       &source,
                       backend.get(),
                       physics ? &*physics : nullptr,
                       detail::SurveyPoints{&in.scene, sim != nullptr, source.sub_rays(),
                                            physics ? physics->max_returns() : 1, colours},
                       &sinks,
                       result.pulses,
                       source.sub_rays(),
                       physics ? physics->max_returns() : 1};
    // At most chunk_pulses (rounded up to whole blocks) in flight between the oldest block not
    // yet written and the newest one taken.
    const std::size_t window =
        (std::max<std::size_t>(1, run.chunk_pulses) + detail::kBlockPulses - 1) /
        detail::kBlockPulses;
    result.points = stream_blocks(stages, sinks, window, pool, progress, run.cancel);
    throw_if_cancelled(run.cancel, "survey");
    result.outputs = sinks.commit();
    result.notes = sinks.notes();
    if (created) {
        created->keep();
    }
    result.survey_s = seconds_since(t0);
    result.few_points_reasons =
        detail::diagnose_survey(spec, *in.pattern, *in.trajectory, *backend,
                                in.scene.geometry.bounds(), result.pulses, result.points, pool);
    return result;
}

}  // namespace beamtrace
