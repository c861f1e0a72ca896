// `beamtrace survey`: a scanner on a platform flies or drives through a scene; every pulse is
// traced and the points are streamed to the output sinks (LAS 1.4, and as asked CSV, PLY, PCD...).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/cancel.hpp"
#include "beamtrace/core/progress.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/sensor/image_pattern.hpp"
#include "beamtrace/sensor/line_scanner.hpp"
#include "beamtrace/sensor/rotating_scanner.hpp"
#include "beamtrace/sensor/scan_pattern_registry.hpp"
#include "beamtrace/sensor/trajectory.hpp"

namespace beamtrace {

enum class PlatformKind : std::uint8_t { fixed, legs, trajectory };

/// One leg's scanner (`platform.legs[i].scanner`, docs/survey.md "Legs"): on or off, and the
/// survey's `scanner:` settings with the leg's overrides.
struct LegScanner {
    bool active = true;  ///< false: no pulse on this leg (e.g. a turn)
    /// The leg's settings (the survey's type and keys, the leg's keys replacing them); nullopt:
    /// the survey's `scanner:` as it is.
    std::optional<ScannerSpec> scanner;
};

/// What a point's LAS point source ID holds (output.point_source_id).
enum class PointSourceId : std::uint8_t {
    part,     ///< the scene part's id (the default)
    leg,      ///< the index of the platform leg that fired the pulse (needs platform.legs)
    scanner,  ///< the index in `scanners:` of the scanner that fired it (0 with one scanner)
};

/// The most scanners on one platform: one per LAS scanner channel (0-3).
inline constexpr std::size_t kMaxSurveyScanners = 4;

/// One scanner of a survey's `scanners:` list (docs/survey.md "Several scanners"): its settings,
/// its place on the platform, its range gate and the LAS scanner channel of its points.
struct SurveyScanner {
    ScannerSpec scanner;       ///< a type of the scan pattern registry and its settings
    Mount mount;               ///< lever arm and boresight on the platform
    double range_min_m = 0.0;  ///< this scanner's range gate
    double range_max_m = std::numeric_limits<double>::infinity();
    std::uint8_t channel = 0;  ///< LAS scanner channel, 0-3 (default: the index in the list)
    /// With platform.legs: one per leg, the leg's settings for this scanner (the leg's
    /// `scanner:` overrides applied to every scanner). Empty: firing for its duration_s.
    std::vector<LegScanner> leg_scanners;
};

/// Everything a survey file says. Parsed by load_survey_spec (see docs/survey.md).
struct SurveySpec {
    std::filesystem::path source;      ///< the survey file
    std::filesystem::path scene_file;  ///< empty: the embedded demo scene
    /// The scanner: a type of the scan pattern registry and its settings (a value: SurveySpec
    /// stays copyable). Default: a rotating VLP-16, one revolution.
    ScannerSpec scanner;
    double range_min_m = 0.0;  ///< closer hits are not recorded
    double range_max_m = std::numeric_limits<double>::infinity();
    PlatformKind platform = PlatformKind::fixed;
    Pose fixed_pose;        ///< platform pose for `fixed`
    LinearLegsConfig legs;  ///< for `legs`
    /// For `legs` with `platform.legs`: one per leg (waypoint k to k + 1), each with its own
    /// scanner settings; the pattern is then a LegSequence (each leg's scanner firing for the
    /// leg's flight time). Empty: one scanner for the whole survey, firing for its duration_s.
    std::vector<LegScanner> leg_scanners;
    std::filesystem::path trajectory_file;  ///< for `trajectory`
    Mount mount;                            ///< lever arm and boresight
    /// `scanners:` (several scanners on the platform, each with its mount, range gate and LAS
    /// scanner channel); empty: the one `scanner:` with `mount:`. When not empty, scanner,
    /// mount, range_min_m, range_max_m and leg_scanners hold its first entry's (what reads one
    /// scanner: the physics' data-sheet defaults, the few-points diagnosis).
    std::vector<SurveyScanner> scanners;
    /// LAS point format: 6, 7 or 8; with physics.waveform.keep 9 (from 6) or 10 (from 7, 8).
    int point_format = 6;
    /// Where format 9/10 wave packets go (output.wave_packets): points.wdp or an EVLR.
    LasWaveformStorage wave_packets = LasWaveformStorage::external;
    /// The switchable outputs turned on by `output: {<key>: true}`: names of point sinks of the
    /// registry (io/point_sink_registry.hpp), e.g. "ply", "csv", "pcd", "laz" (points.laz).
    /// "las" (points.las) and "preview" (preview.png) are on by default (`las: false`,
    /// `preview: false` turn them off); waveforms, images and the trajectory are written
    /// whenever the survey calls for them.
    std::vector<std::string> outputs{"las", "preview"};
    double trajectory_rate_hz = 10.0;  ///< samples per second in trajectory.csv (0: none)
    /// output.extra_bytes: the attributes every point of points.las / points.laz carries as
    /// LAS extra bytes, in that order (io/point_attributes.hpp); empty (the default): none.
    std::vector<PointAttribute> extra_bytes;
    /// output.point_source_id: the LAS point source ID of every point (default: the part's id).
    PointSourceId point_source_id = PointSourceId::part;
    std::string text;  ///< the file's text (recorded in the LAS VLR)
    /// The `physics:` block (docs/physics.md) with the `weather:` block (docs/weather.md) in
    /// physics->weather; nullopt: ideal single rays, no intensity/noise (a `weather:` block
    /// alone gives the physics' defaults).
    std::optional<PhysicsConfig> physics;

    /// The scan pattern described by the file: the scanner's, or with leg_scanners a
    /// LegSequence (sensor/leg_sequence.hpp) of the legs' scanners over the legs' flight times;
    /// with `scanners:` a ScannerSet (sensor/scanner_set.hpp) of each scanner's pattern.
    [[nodiscard]] std::unique_ptr<ScanPattern> make_pattern() const;
    /// The platform's trajectory.
    [[nodiscard]] std::unique_ptr<Trajectory> make_trajectory() const;
};

/// Parses a survey file; throws ConfigError listing every problem as `file:line: key: what`.
[[nodiscard]] SurveySpec load_survey_spec(const std::filesystem::path& path);
[[nodiscard]] SurveySpec parse_survey_spec(const std::string& yaml_text,
                                           const std::filesystem::path& source);

/// Makes a sink from the facts of the run (SurveyRunConfig::extra_sinks).
using SinkFactory = std::function<std::unique_ptr<PointSink>(const SinkFacts& facts)>;

struct SurveyRunConfig {
    std::filesystem::path output_dir;  ///< where the files go (unused without write_files)
    unsigned threads = 0;              ///< 0 = all cores; results identical for any value
    std::uint64_t seed = 1;  ///< recorded in the LAS VLR; keys the physics noise (counter RNG)
    BackendKind backend = default_backend_kind();
    /// Most pulses in flight between the oldest block not yet written and the newest one taken
    /// (rounded up to whole blocks of 1024 pulses): bounds the memory of the outputs.
    std::size_t chunk_pulses = std::size_t{1} << 16;
    /// Stop after this many pulses (the first ones; previews and benchmarks). 0: all of them.
    std::uint64_t max_pulses = 0;
    /// Checked between blocks: once requested, run_survey stops, removes its temporary files
    /// (and the output directory, if it created it and it is empty) and throws Interrupted.
    /// Null: the survey runs to the end. The token must outlive the call.
    const CancelToken* cancel = nullptr;
    /// Sinks fed the same points as the file outputs, after them (e.g. make_callback_sink of
    /// io/callback_sink.hpp: the points in memory); each factory is called once, before the
    /// first point. Empty: none.
    std::vector<SinkFactory> extra_sinks;
    /// false: the survey file's outputs (points.las, preview.png...) are not written and
    /// output_dir is not used; only extra_sinks get the points.
    bool write_files = true;
};

struct SurveyResult {
    std::uint64_t pulses = 0;
    std::uint64_t points = 0;
    /// With a `weather:` block: the points the weather made (fog, rain, snow), among `points`
    /// (not counted by run_survey_distributed).
    std::optional<std::uint64_t> weather_points;
    std::size_t triangles = 0;
    std::size_t spheres = 0;  ///< exact spheres
    /// With physics: the LAS intensity reference range R_ref in use [m], whether it was `auto`
    /// (half the nominal range), and the pilot's nominal range (auto; none when it hit nothing).
    std::optional<double> intensity_reference_range_m;
    bool intensity_reference_auto = false;
    std::optional<double> nominal_range_m;
    double build_s = 0, survey_s = 0;
    std::vector<std::filesystem::path> outputs;
    std::vector<std::string> notes;  ///< the outputs' lines for the summary (range.png's span)
    /// When the survey gave no or very few points (fewer than 0.1 % of its pulses): why it may
    /// be, a line each (the scanner looks away from the scene, hits outside the range gate,
    /// returns below the detection threshold); empty otherwise.
    std::vector<std::string> few_points_reasons;
};

/// The rays run_survey traces for the first `max_pulses` pulses (0: all), in pulse order with
/// the physics' sub-rays of a pulse side by side: the same values bit for bit. For benchmarks.
[[nodiscard]] RayBatch survey_rays(const SurveySpec& spec, std::uint64_t seed,
                                   std::uint64_t max_pulses, ThreadPool& pool);

/// Runs the survey: memory stays bounded by the chunk size whatever the number of pulses.
/// Throws Interrupted when run.cancel is requested before the outputs are committed; the
/// output directory is then left as it was.
[[nodiscard]] SurveyResult run_survey(const SurveySpec& spec, const SurveyRunConfig& run,
                                      const ProgressFn& progress = {});

}  // namespace beamtrace
