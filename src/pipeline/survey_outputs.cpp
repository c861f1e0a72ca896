#include "pipeline/detail/survey_outputs.hpp"

#include <algorithm>
#include <cmath>

#include "beamtrace/io/point_sink_registry.hpp"

namespace beamtrace::detail {

std::optional<SampledTrajectory> survey_trajectory_samples(const SurveySpec& spec,
                                                           const ScanPattern& pattern,
                                                           const Trajectory& trajectory,
                                                           const Vec3d& origin_m,
                                                           std::uint64_t pulses) {
    if (!(spec.trajectory_rate_hz > 0) || pulses == 0) {
        return std::nullopt;
    }
    std::vector<TrajectorySample> samples;
    const double start = pattern.start_time_s(), end = pattern.end_time_s();
    const auto n = static_cast<std::size_t>(std::floor((end - start) * spec.trajectory_rate_hz));
    for (std::size_t k = 0; k <= n + 1; ++k) {
        const double time = std::min(end, start + static_cast<double>(k) / spec.trajectory_rate_hz);
        if (!samples.empty() && time <= samples.back().time_s) {
            break;
        }
        const Pose pose = trajectory.pose_at(time);
        samples.push_back({time, pose.position_m + origin_m, to_rpy(pose.attitude)});
    }
    if (samples.size() == 1) {
        samples.push_back({samples[0].time_s + 1.0 / spec.trajectory_rate_hz, samples[0].position_m,
                           samples[0].attitude});
    }
    return SampledTrajectory(samples);
}

SinkFacts survey_sink_facts(const SurveySpec& spec, const SurveyRunConfig& run, const Scene& scene,
                            const ScanPattern& pattern, const Trajectory& trajectory,
                            const PulseSimulator* sim, std::uint64_t pulses) {
    SinkFacts f;
    f.output_dir = run.output_dir;
    f.physics = sim != nullptr;
    const Aabb bounds = scene.geometry.bounds();
    f.lo_m = Vec3d(bounds.lo) + scene.origin_m;
    f.hi_m = Vec3d(bounds.hi) + scene.origin_m;
    f.las_point_format = spec.point_format;
    f.pulses = pulses;
    f.crs_wkt = scene.crs.wkt;
    f.provenance = "# beamtrace " BEAMTRACE_VERSION " survey, seed " + std::to_string(run.seed) +
                   "\n" + spec.text;
    f.comment = "beamtrace survey " + spec.source.filename().string();
    f.image = pattern.image_grid();
    if (sim != nullptr && sim->config().keep_waveform) {
        const PhysicsConfig& c = sim->config();
        f.waveform = WaveformFacts{c.waveform.bin_ns, c.waveform.pulse_fwhm_ns,
                                   c.radiometry.detection_threshold_w, c.radiometry.peak_power_w,
                                   spec.wave_packets};
    }
    f.trajectory = survey_trajectory_samples(spec, pattern, trajectory, scene.origin_m, pulses);
    f.trajectory_rate_hz = spec.trajectory_rate_hz;
    f.extra_bytes = spec.extra_bytes;
    f.scanners = spec.scanners.size();
    return f;
}

SinkSet open_survey_sinks(const SurveySpec& spec, const SinkFacts& facts) {
    SinkSet sinks;
    for (const SinkEntry& e : point_sinks()) {
        const bool chosen = e.key.empty() || std::find(spec.outputs.begin(), spec.outputs.end(),
                                                       e.name) != spec.outputs.end();
        if (chosen && e.applies(facts)) {
            sinks.add(e.make(facts));
        }
    }
    return sinks;
}

SinkSet open_run_sinks(const SurveySpec& spec, const SurveyRunConfig& run, const SinkFacts& facts) {
    SinkSet sinks = run.write_files ? open_survey_sinks(spec, facts) : SinkSet{};
    for (const SinkFactory& make : run.extra_sinks) {
        if (make) {
            sinks.add(make(facts));
        }
    }
    return sinks;
}

}  // namespace beamtrace::detail
