// `beamtrace survey`: the stages (poses and rays, trace, physics, points) of each block of
// pulses on the pool threads, the sinks' encoding beside them, the sinks' writes in block order
// by whichever pool thread completes the next block in order, or on a writer thread where the
// pool leaves a core idle, which then encodes them too (docs/dev/architecture-pipeline.md).
#include <algorithm>
#include <chrono>
#include <optional>
#include <system_error>
#include <utility>

#include "beamtrace/core/cancel.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/sensor/leg_sequence.hpp"
#include "beamtrace/sensor/scanner_set.hpp"
#include "core/created_dirs.hpp"
#include "pipeline/detail/ordered_blocks.hpp"
#include "pipeline/detail/survey_block.hpp"
#include "pipeline/detail/survey_outputs.hpp"
#include "pipeline/detail/survey_rays.hpp"
#include "pipeline/detail/survey_session.hpp"

namespace beamtrace {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

void create_output_dir(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) {
        throw OutputError(dir.string() + ": cannot create output directory" +
                          (ec ? ": " + ec.message() : std::string()));
    }
}

/// Writing on the pool threads where they take every core; a writer thread of its own where the
/// pool leaves a core idle (e.g. one thread on a two-core machine), which then writes for free.
/// The cores are those the process may run on: an MPI rank bound to one core has no idle one.
detail::BlockWriter block_writer(const ThreadPool& pool) {
    return pool.size() < available_cores() ? detail::BlockWriter::own_thread
                                           : detail::BlockWriter::combining;
}

/// Runs every block of `session` on the pool, encodes it for `sinks` beside it and writes them
/// to `sinks` in block order, with at most `window` blocks in flight; returns the number of
/// points written and of the weather's among them. Checks `cancel` before each block is taken and
/// written: Interrupted stops every thread.
std::pair<std::uint64_t, std::uint64_t> stream_blocks(const detail::SurveySession& session,
                                                      detail::SinkSet& sinks, std::size_t window,
                                                      ThreadPool& pool, const ProgressFn& progress,
                                                      const CancelToken* cancel) {
    const std::uint64_t pulses = session.pulses();
    const std::size_t blocks = session.blocks();
    const std::size_t progress_every = std::max<std::size_t>(1, window / 4);
    std::uint64_t points = 0, weather_points = 0;
    const detail::BlockWriter mode = block_writer(pool);
    // A writer thread of its own has a core to itself: it encodes the blocks too (LAS records,
    // preview pixels), off the pool's thread. Their points wait in the window, and come back.
    const bool writer_encodes = mode == detail::BlockWriter::own_thread;
    detail::Shelf<PointBlock> spare_points;
    detail::OrderedBlocks ordered(
        blocks, window,
        [&](std::size_t k, detail::BlockOutput& out) {
            throw_if_cancelled(cancel, "survey");  // finish() rethrows it
            if (out.deferred) {
                sinks.encode(out.pending, out);
                spare_points.put(std::exchange(out.pending, PointBlock{}));
            }
            sinks.write(out);
            points += out.points;
            weather_points += out.weather_points;
            if (progress && ((k + 1) % progress_every == 0 || k + 1 == blocks)) {
                progress(static_cast<std::size_t>(
                             std::min<std::uint64_t>((k + 1) * detail::kBlockPulses, pulses)),
                         static_cast<std::size_t>(pulses));
            }
        },
        mode);
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
                session.run_block(k, *work);
                // While the writer keeps up; one behind by half the window (its core taken by
                // other work) leaves the encoding to the pool again, until it has caught up.
                if (writer_encodes && ordered.behind(k) < window / 2) {
                    out->pending = std::exchange(work->points, spare_points.take());
                    out->deferred = true;
                } else {
                    sinks.encode(work->points, *out);
                }
                shelf.put(std::move(work));
            } catch (...) {
                ordered.abort();
                throw;
            }
            ordered.publish(k);
        }
    });
    ordered.finish();
    return {points, weather_points};
}

}  // namespace

namespace {

/// One scanner's pattern: its own, or with `leg_scanners` a LegSequence of its legs' scanners
/// over the legs' flight times.
std::unique_ptr<ScanPattern> scanner_pattern(const ScannerSpec& scanner,
                                             const std::vector<LegScanner>& leg_scanners,
                                             const LinearLegsConfig& legs) {
    if (leg_scanners.empty()) {
        return scanner.make_pattern();
    }
    const LinearLegs path(legs);
    const std::vector<double>& t = path.waypoint_times_s();
    if (leg_scanners.size() + 1 != t.size()) {
        throw ConfigError("platform.legs: " + std::to_string(leg_scanners.size()) + " legs for " +
                          std::to_string(t.size()) + " waypoints");
    }
    std::vector<SequenceLeg> seq;
    for (std::size_t l = 0; l < leg_scanners.size(); ++l) {
        SequenceLeg& leg = seq.emplace_back();
        leg.start_time_s = t[l];
        leg.end_time_s = t[l + 1];
        const LegScanner& ls = leg_scanners[l];
        if (ls.active) {
            const ScannerSpec& own = ls.scanner ? *ls.scanner : scanner;
            const auto timed = own.settings().with_timing(t[l], t[l + 1] - t[l]);
            if (!timed) {
                throw ConfigError("platform.legs: a " + own.type() +
                                  " scanner has no duration_s to fire for a leg's flight time");
            }
            leg.pattern = timed->make_pattern();
        }
    }
    return std::make_unique<LegSequence>(std::move(seq));
}

}  // namespace

std::unique_ptr<ScanPattern> SurveySpec::make_pattern() const {
    if (scanners.empty()) {
        return scanner_pattern(scanner, leg_scanners, legs);
    }
    std::vector<std::unique_ptr<ScanPattern>> each;
    for (const SurveyScanner& s : scanners) {
        each.push_back(scanner_pattern(s.scanner, s.leg_scanners, legs));
    }
    return std::make_unique<ScannerSet>(std::move(each));
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
    ThreadPool pool(run.threads);
    const detail::SurveySession session(spec, run, pool);
    SurveyResult result = session.result();
    throw_if_cancelled(run.cancel, "survey");
    // Declared before the sinks: on an error or interrupt the sinks remove their temporaries
    // first, then the folders this run created go if empty.
    std::optional<CreatedDirs> created;
    if (run.write_files) {
        created.emplace(run.output_dir);
        create_output_dir(run.output_dir);
    }
    detail::SinkSet sinks = detail::open_run_sinks(spec, run, session.facts());
    const auto t0 = Clock::now();
    // At most chunk_pulses (rounded up to whole blocks) in flight between the oldest block not
    // yet written and the newest one taken.
    const std::size_t window =
        (std::max<std::size_t>(1, run.chunk_pulses) + detail::kBlockPulses - 1) /
        detail::kBlockPulses;
    const auto [points, weather_points] =
        stream_blocks(session, sinks, window, pool, progress, run.cancel);
    result.points = points;
    if (spec.physics && spec.physics->weather) {
        result.weather_points = weather_points;
    }
    throw_if_cancelled(run.cancel, "survey");
    result.outputs = sinks.commit();
    result.notes = sinks.notes();
    if (created) {
        created->keep();
    }
    result.survey_s = seconds_since(t0);
    result.few_points_reasons = session.diagnose(result.points, pool);
    return result;
}

}  // namespace beamtrace
