// Point sinks: every output of a survey or scan (LAS, CSV, PLY, PCD, waveforms, images, the
// trajectory) behind one small interface, in the spirit of PDAL's streamable writers. A sink is
// opened with the header facts (its factory), encodes blocks of points on any thread, writes the
// encoded blocks in block order on one thread, and finally commits (its files appear complete)
// or aborts (nothing appears). The registry (point_sink_registry.hpp) names them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/point_attributes.hpp"
#include "beamtrace/sensor/scan_pattern.hpp"
#include "beamtrace/sensor/trajectory.hpp"

namespace beamtrace {

/// One point of a block: what any sink may record of a return. The LAS fields (world xyz,
/// GPS time, scan angle, intensity, point source ID = the part's id, return number and count,
/// classification = the part's label, user data = the channel's low byte) are those of
/// LasSimplePoint, so the LAS sink encodes a BlockPoint as it is.
struct BlockPoint : LasSimplePoint {
    float range_m = 0.0f;       ///< distance from the beam origin
    std::uint32_t face = 0;     ///< face of the hit (PLY face_id)
    std::uint16_t channel = 0;  ///< beam / row of the scanner
    std::uint64_t pulse = 0;    ///< pulse (or ray) index: PLY `ray`, image pixel
    /// Angle between the beam (physics: the sub-ray that dominated the return) and the hit
    /// surface's normal, 0 to 90 degrees. Filled when the LAS extra bytes ask for it.
    float incidence_deg = 0.0f;
    /// FWHM of the return's echo (physics only; NaN without: unknown).
    float echo_width_ns = std::numeric_limits<float>::quiet_NaN();
    /// What weather made the echo (WeatherEffect: 0 none, 1 fog, 2 rain, 3 snow); its point
    /// has no face (kNoFace), part 0 and the weather's LAS class.
    std::uint8_t weather = 0;
    /// The hit object (Scene::object_of_face) and its velocity there at the pulse's time (m/s;
    /// 0 for still parts). Filled when the LAS extra bytes ask for them.
    std::uint32_t instance_id = 0;
    Vec3f velocity_mps{0.0f, 0.0f, 0.0f};
};

/// One pulse's sampled echo (physics.waveform.keep): samples [first_sample, + count) of the block.
struct PulseWaveform {
    std::uint64_t pulse = 0;
    double time_s = 0.0;
    Vec3d origin_m;  ///< beam origin, world
    Vec3d axis;      ///< beam axis (unit)
    std::int64_t first_bin = 0;
    std::size_t first_sample = 0;
    std::uint32_t count = 0;
};

/// A pulse that gave no point (output.no_echo): for gap studies.
struct NoEchoPulse {
    std::uint64_t pulse = 0;
    double time_s = 0.0;       ///< GPS time of emission
    Vec3d origin_m;            ///< beam origin, world (as the points are placed)
    Vec3d axis;                ///< beam axis (unit), world
    std::uint8_t scanner = 0;  ///< the index of the scanner that fired it (`scanners:`)
};

/// A block of consecutive pulses' points, in pulse order (a pulse's returns side by side).
struct PointBlock {
    std::vector<BlockPoint> points;
    std::vector<PulseWaveform> waveforms;  ///< empty unless waveforms are kept
    std::vector<float> samples;            ///< the waveforms' samples, watts
    std::vector<NoEchoPulse> no_echo;      ///< empty unless output.no_echo is on; pulse order
    /// Empties the block (keeps its memory).
    void clear() {
        points.clear();
        waveforms.clear();
        samples.clear();
        no_echo.clear();
    }
};

/// What the waveform record's file header says.
struct WaveformFacts {
    double bin_ns = 0.5;
    double pulse_fwhm_ns = 4.0;
    /// The receiver's detection threshold and the emitted peak power: the wave packets'
    /// digitiser gain (src/io/sinks/wave_packet_stream.hpp).
    double detection_threshold_w = 1e-8;
    double peak_power_w = 1000.0;
    /// Where points.las (formats 9, 10) keeps its wave packets: points.wdp or an EVLR.
    LasWaveformStorage storage = LasWaveformStorage::external;
};

/// The header facts every sink may need, known before the first point: the schema and the
/// settings of the run. Sinks take what they use.
struct SinkFacts {
    std::filesystem::path output_dir;
    bool physics = false;  ///< intensity and return numbers are simulated (CSV columns)
    Vec3d lo_m, hi_m;      ///< world bounds of the scene (LAS scale and offset)
    /// Where most points will be (world; the survey's pilot hits, grown): preview.png's frame.
    /// Unset: lo_m, hi_m.
    std::optional<std::pair<Vec3d, Vec3d>> footprint_m;
    std::uint64_t pulses = 0;  ///< pulses of the run (0: unknown): preview.png's pixel size
    int las_point_format = 6;
    std::string provenance;  ///< recorded in the LAS VLR (version, seed, survey file)
    std::string crs_wkt;     ///< the scene's CRS, an OGC WKT VLR of the LAS output (empty: none)
    std::string comment;     ///< PLY header comment
    std::optional<ImageGrid> image;
    bool image_labels = true;  ///< labels.png besides range.npy and range.png
    std::optional<WaveformFacts> waveform;
    /// The platform's samples for trajectory.csv (none: no trajectory output).
    std::optional<SampledTrajectory> trajectory;
    double trajectory_rate_hz = 0.0;
    /// The attributes points.las and points.laz carry as LAS extra bytes, in record order
    /// (output.extra_bytes); empty: none (the records are the bare point format).
    std::vector<PointAttribute> extra_bytes;
    /// The entries of the survey's `scanners:` (0: one `scanner:`); with any, no_echo.csv has a
    /// `scanner` column.
    std::size_t scanners = 0;
};

/// What a sink encodes from one block, on a pool thread, for its write(). Reused block to block.
class SinkBuffer {
  public:
    virtual ~SinkBuffer() = default;
    /// Empties the buffer (keeps its memory).
    virtual void clear() = 0;
};

/// The common SinkBuffer: bytes to append to a file.
struct ByteBuffer final : SinkBuffer {
    std::string bytes;
    void clear() override { bytes.clear(); }
};

/// One output. The factory opens it (temporary files); then encode() on any threads, write()
/// in block order on one thread, and commit() once. Destroyed without commit() — or after
/// abort() — it leaves no file. Errors throw OutputError naming the file.
class PointSink {
  public:
    PointSink() = default;
    virtual ~PointSink() = default;
    PointSink(const PointSink&) = delete;
    PointSink& operator=(const PointSink&) = delete;
    PointSink(PointSink&&) = delete;
    PointSink& operator=(PointSink&&) = delete;

    /// A buffer for encode().
    [[nodiscard]] virtual std::unique_ptr<SinkBuffer> make_buffer() const;
    /// Encodes `block` into `out` (empty on entry). Thread-safe: called on pool threads, on
    /// different blocks at once, in any order.
    virtual void encode(const PointBlock& block, SinkBuffer& out) const = 0;
    /// Appends an encoded block; one thread, blocks in order.
    virtual void write(const SinkBuffer& encoded) = 0;
    /// Finishes the files and renames them into place; returns them. Called once.
    [[nodiscard]] virtual std::vector<std::filesystem::path> commit() = 0;
    /// True when commit() may run on a thread of its own, beside the other sinks' commits (it
    /// touches nothing but the sink and its own files): a sink whose commit is long work for
    /// the CPU (preview.png) then overlaps one that waits for the disk (points.las).
    [[nodiscard]] virtual bool commits_beside() const { return false; }
    /// Removes whatever was written; the sink accepts nothing afterwards.
    virtual void abort() noexcept = 0;
    /// After commit(): lines for the run's summary (e.g. the span of range.png's colours).
    [[nodiscard]] virtual std::vector<std::string> notes() const { return {}; }
};

}  // namespace beamtrace
