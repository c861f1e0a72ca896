// `beamtrace scan` as one library call: load the scene, cast the sensor's rays, trace them and
// write the outputs chosen (ScanOutputs): by default points.ply and, for image patterns,
// range.npy; range.png, hits.csv and points.laz on request.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/cancel.hpp"
#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/progress.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/pipeline/face_filter.hpp"
#include "beamtrace/scene/scene.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "beamtrace/sensor/scan_pattern_registry.hpp"

namespace beamtrace {

/// A `beamtrace scan` pattern of the scan pattern registry ("pinhole", "scan" or "rays", see
/// static_scan_pattern_choices()): returns the name; throws ConfigError listing them otherwise.
[[nodiscard]] std::string parse_pattern_kind(std::string_view name);

/// The sensor options of `beamtrace scan`, each applied only when given, over the sensor the
/// scan starts from: ImageSensorConfig's defaults, or the demo scene's (demo_sensor()) with
/// `demo`. See ScanJobConfig::apply.
struct ScanSensorOptions {
    std::optional<Vec3d> position_m;
    std::optional<Vec3d> orientation_rad;  ///< roll, pitch, yaw
    /// Pixels; for a rays file, the size of its range images (width x height = ray count).
    std::optional<int> width, height;
    std::optional<double> hfov_rad, vfov_rad;
};

/// "sah" (binned SAH, the default) or "report" (the ladar report's rules): the k-d tree's build
/// settings; throws ConfigError listing the two otherwise.
[[nodiscard]] KdTreeBuildConfig parse_kdtree_rules(std::string_view name);

/// What `beamtrace scan` writes (`--outputs`). The default is the data a LiDAR user reads back:
/// the point cloud and the range image. The quick look (range.png: its colour map and zlib cost
/// as much as both), the per-ray CSV table (the largest and slowest to write) and the compressed
/// LAZ copy are on request.
struct ScanOutputs {
    bool ply = true;   ///< points.ply: the hits, binary little-endian
    bool npy = true;   ///< range.npy: the range image (image grids only)
    bool png = false;  ///< range.png: the range image colour-mapped (image grids only)
    bool csv = false;  ///< hits.csv: one text row per ray, misses too
    bool laz = false;  ///< points.laz: the points of points.ply as LAS 1.4, LASzip-compressed
    bool operator==(const ScanOutputs&) const = default;
};

/// Parses `--outputs`: a comma-separated list of ply, npy, png, csv, laz (each at most once, at
/// least one). Throws ConfigError naming the bad item and the choices.
[[nodiscard]] ScanOutputs parse_scan_outputs(std::string_view list);
/// The list form of `outputs` ("ply,npy" for the default), in the order of the choices.
[[nodiscard]] std::string to_string(const ScanOutputs& outputs);
/// "ply, npy, png, csv, laz": the names parse_scan_outputs takes, for help texts.
[[nodiscard]] std::string scan_output_choices();

struct ScanJobConfig {
    std::vector<std::filesystem::path> meshes;  ///< OBJ/PLY/STL files, concatenated in order
    bool demo = false;                          ///< use the embedded demo scene instead
    /// A registry pattern offered by scan (scan_pattern_registry.hpp).
    std::string pattern = "pinhole";
    ImageSensorConfig sensor;         ///< for pinhole and scan
    std::filesystem::path rays_file;  ///< for rays: CSV ox,oy,oz,dx,dy,dz
    /// For rays: write range images of this width x height (must equal the ray count).
    std::optional<int> image_width, image_height;
    BackendKind backend = default_backend_kind();
    BackendConfig backend_config;  ///< build settings (e.g. the k-d tree's rules)
    unsigned threads = 0;          ///< 0 = all hardware threads
    std::filesystem::path output_dir;
    std::vector<FaceRange> exclude_faces;  ///< hits on these faces are left out of points.ply
    /// The files to write. range.npy and range.png need an image grid (pinhole, scan, or rays
    /// with image_width x image_height); without one they are skipped. points.laz holds the
    /// points of points.ply as LAS 1.4 format 6 (coordinates to 1 mm around the hits' centre).
    ScanOutputs outputs;
    /// Checked between chunks of rays (tracing and writing): once requested, run_scan stops,
    /// removes its temporary files and throws Interrupted. Null: runs to the end.
    const CancelToken* cancel = nullptr;

    /// Sets `sensor` (from the demo's sensor when `demo`), or for a rays file the image size,
    /// from the options given. Call after `demo` and `pattern` are set.
    void apply(const ScanSensorOptions& options);
    /// Every problem at once; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
    /// Whether `pattern` reads its rays from rays_file (rays) rather than casting them from
    /// `sensor`; false for an unknown pattern.
    [[nodiscard]] bool reads_rays_file() const;
};

struct ScanResult {
    std::size_t triangles = 0;
    std::size_t rays = 0;
    std::size_t hits = 0;
    std::size_t points_written = 0;  ///< hits minus excluded faces
    std::vector<ScenePart> parts;
    std::vector<std::filesystem::path> outputs;
    std::vector<std::string> notes;  ///< the outputs' lines for the summary (range.png's span)
    double load_s = 0, build_s = 0, trace_s = 0, write_s = 0;
    /// When fewer than 0.1 % of the rays hit: why it may be, a line each; empty otherwise.
    std::vector<std::string> few_hits_reasons;
};

/// What write_scan_outputs wrote.
struct ScanWritten {
    std::size_t hits = 0;            ///< rays that hit
    std::size_t points_written = 0;  ///< hits minus excluded faces; 0 without ply and laz
    std::vector<std::filesystem::path> outputs;  ///< in the order ply, npy, png, csv, laz
    std::vector<std::string> notes;              ///< the outputs' summary lines
};

/// The writing half of run_scan, on the pool's threads: the outputs config.outputs selects, into
/// config.output_dir (created if missing), for `hits` of `rays` (hit i of ray i). The range
/// images have `width` x `height` pixels, pixel (v, u) of ray u * height + v; 0 x 0: none (npy
/// and png are skipped). Only config.output_dir, outputs, exclude_faces, backend (named in
/// points.ply) and cancel are read. Throws OutputError or Interrupted, leaving none of the
/// outputs (nor the folder, when it created it).
[[nodiscard]] ScanWritten write_scan_outputs(const ScanJobConfig& config, const RayBatch& rays,
                                             const HitBatch& hits, int width, int height,
                                             ThreadPool& pool);

/// Runs the scan. Throws ConfigError, InputError or OutputError with context; outputs appear
/// only complete (each is written to a temporary file and renamed).
[[nodiscard]] ScanResult run_scan(const ScanJobConfig& config, const ProgressFn& progress = {});

}  // namespace beamtrace
