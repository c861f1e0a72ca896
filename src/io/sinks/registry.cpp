#include "beamtrace/io/point_sink_registry.hpp"

#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

// The factories, one per file of src/io/sinks.
std::unique_ptr<PointSink> make_las_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_laz_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_waveform_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_csv_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_image_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_ply_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_trajectory_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_pcd_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_preview_sink(const SinkFacts& facts);
std::unique_ptr<PointSink> make_no_echo_sink(const SinkFacts& facts);

namespace {

bool always(const SinkFacts& /*facts*/) {
    return true;
}
bool with_waveforms(const SinkFacts& facts) {
    return facts.waveform.has_value();
}
bool with_image(const SinkFacts& facts) {
    return facts.image.has_value();
}
bool with_trajectory(const SinkFacts& facts) {
    return facts.trajectory.has_value();
}

}  // namespace

std::span<const SinkEntry> point_sinks() {
    // name, files, survey output key, what, when it applies, factory
    static constexpr SinkEntry kSinks[] = {
        {"las", "points.las", "las", "LAS 1.4 points (format output.point_format)", always,
         make_las_sink},
        {"laz", "points.laz", "laz", "the LAS points LASzip-compressed (LAZ)", always,
         make_laz_sink},
        {"waveforms", "waveforms.bin", "", "every pulse's sampled echo (physics.waveform.keep)",
         with_waveforms, make_waveform_sink},
        {"csv", "points.csv", "csv", "the points as CSV", always, make_csv_sink},
        {"images", "range.npy, range.png, labels.png", "",
         "range and label images (image scanner, one frame)", with_image, make_image_sink},
        {"ply", "points.ply", "ply", "binary PLY: x y z range face_id ray", always, make_ply_sink},
        {"trajectory", "trajectory.csv", "", "the platform at output.trajectory_rate_hz",
         with_trajectory, make_trajectory_sink},
        {"pcd", "points.pcd", "pcd", "binary PCD (Point Cloud Library)", always, make_pcd_sink},
        {"preview", "preview.png", "preview",
         "a top-down quick look: heights in colour, hill-shaded, with a scale bar (on unless "
         "output.preview: false)",
         always, make_preview_sink},
        {"no_echo", "no_echo.csv", "no_echo",
         "every pulse that gave no point: pulse, GPS time, beam origin and direction", always,
         make_no_echo_sink},
    };
    return kSinks;
}

const SinkEntry& point_sink(std::string_view name) {
    std::string known;
    for (const SinkEntry& e : point_sinks()) {
        if (e.name == name) {
            return e;
        }
        known += (known.empty() ? "" : ", ") + std::string(e.name);
    }
    throw ConfigError("unknown output '" + std::string(name) + "' (known: " + known + ")");
}

}  // namespace beamtrace
