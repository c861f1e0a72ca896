#include "beamtrace/pipeline/scan_job.hpp"

#include <chrono>
#include <cmath>
#include <system_error>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/colormap.hpp"
#include "beamtrace/io/hits_csv.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/sensor/rays_file.hpp"

namespace beamtrace {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr std::size_t kTraceChunk = std::size_t{1} << 16;

void prepare_output_dir(const std::filesystem::path& dir) {
    std::error_code ec;
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
        throw OutputError(dir.string() + ": output path exists and is not a directory");
    }
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        throw OutputError(dir.string() + ": cannot create output directory: " + ec.message());
    }
}

/// Range image in row-major (row v, column u) order, misses 0, like the report's raysToImg.
std::vector<float> range_image(const HitBatch& hits, int width, int height) {
    std::vector<float> img(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            const std::size_t i = ray_index(u, v, height);
            img[static_cast<std::size_t>(v) * static_cast<std::size_t>(width) +
                static_cast<std::size_t>(u)] = hits.hit(i) ? hits.t[i] : 0.0f;
        }
    }
    return img;
}

}  // namespace

std::string parse_pattern_kind(std::string_view name) {
    return std::string(static_scan_pattern(name).name);
}

bool ScanJobConfig::reads_rays_file() const {
    const ScanPatternEntry* e = find_scan_pattern(pattern);
    return e != nullptr && e->reads_rays_file;
}

std::vector<std::string> ScanJobConfig::validate() const {
    std::vector<std::string> p;
    if (demo && !meshes.empty()) {
        p.emplace_back("--demo and --mesh are exclusive");
    }
    if (!demo && meshes.empty()) {
        p.emplace_back("no scene: give --mesh FILE (repeatable) or --demo");
    }
    if (output_dir.empty()) {
        p.emplace_back("no output directory (--output DIR)");
    }
    const ScanPatternEntry* e = find_scan_pattern(pattern);
    if (e == nullptr || e->static_rays == nullptr) {
        p.emplace_back("unknown pattern '" + pattern + "' (expected " +
                       static_scan_pattern_choices() + ")");
        return p;
    }
    if (e->reads_rays_file) {
        if (rays_file.empty()) {
            p.emplace_back("--pattern " + pattern + " needs --rays FILE");
        }
        if (image_width.has_value() != image_height.has_value()) {
            p.emplace_back("--width and --height go together");
        } else if (image_width && (*image_width < 1 || *image_height < 1)) {
            p.emplace_back("--width and --height must be at least 1");
        }
    } else if (!rays_file.empty()) {
        p.emplace_back("--rays needs --pattern rays");
    }
    if (e->check_static != nullptr) {
        for (auto& s : e->check_static({sensor, rays_file})) {
            p.push_back(std::move(s));
        }
    }
    return p;
}

ScanResult run_scan(const ScanJobConfig& config, const ProgressFn& progress) {
    const auto problems = config.validate();
    if (!problems.empty()) {
        std::string msg;
        for (const auto& s : problems) {
            msg += (msg.empty() ? "" : "; ") + s;
        }
        throw ConfigError(msg);
    }
    ScanResult result;
    ThreadPool pool(config.threads);

    // Inputs first: nothing is written before they all parse.
    auto t0 = Clock::now();
    Scene scene = config.demo ? make_demo_scene() : load_scene_meshes(config.meshes);
    StaticRays cast =
        static_scan_pattern(config.pattern).static_rays({config.sensor, config.rays_file});
    RayBatch& rays = cast.rays;
    if (!cast.grid && config.image_width) {
        cast.grid = ImageGrid{*config.image_width, *config.image_height};
        if (static_cast<std::size_t>(cast.grid->width) *
                static_cast<std::size_t>(cast.grid->height) !=
            rays.size()) {
            throw ConfigError(config.rays_file.string() + ": has " + std::to_string(rays.size()) +
                              " rays but --width x --height is " +
                              std::to_string(cast.grid->width) + " x " +
                              std::to_string(cast.grid->height));
        }
    }
    const int width = cast.grid ? cast.grid->width : 0;
    const int height = cast.grid ? cast.grid->height : 0;
    result.load_s = seconds_since(t0);
    result.triangles = scene.triangle_count();
    result.parts = scene.parts;
    result.rays = rays.size();

    t0 = Clock::now();
    const auto backend = make_backend(config.backend, scene.geometry, pool, config.backend_config);
    result.build_s = seconds_since(t0);

    t0 = Clock::now();
    HitBatch hits;
    hits.resize(rays.size());
    for (std::size_t b = 0; b < rays.size(); b += kTraceChunk) {
        const std::size_t e = std::min(rays.size(), b + kTraceChunk);
        backend->intersect(rays, b, e, hits, pool);
        if (progress) {
            progress(e, rays.size());
        }
    }
    result.trace_s = seconds_since(t0);

    t0 = Clock::now();
    prepare_output_dir(config.output_dir);
    std::vector<PointRecord> points;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!hits.hit(i)) {
            continue;
        }
        ++result.hits;
        if (in_ranges(config.exclude_faces, hits.face[i])) {
            continue;
        }
        const double t = hits.t[i];
        points.push_back({rays.ox[i] + t * rays.dx[i], rays.oy[i] + t * rays.dy[i],
                          rays.oz[i] + t * rays.dz[i], hits.t[i], hits.face[i],
                          static_cast<std::uint32_t>(i)});
    }
    result.points_written = points.size();

    const auto& dir = config.output_dir;
    write_hits_csv(dir / "hits.csv", hits);
    result.outputs.push_back(dir / "hits.csv");
    write_points_ply(dir / "points.ply", points,
                     "generated by beamtrace " BEAMTRACE_VERSION " scan (backend " +
                         std::string(to_string(config.backend)) + ")");
    result.outputs.push_back(dir / "points.ply");
    if (width > 0 && height > 0) {
        const std::vector<float> img = range_image(hits, width, height);
        write_npy_f32(dir / "range.npy", static_cast<std::size_t>(height),
                      static_cast<std::size_t>(width), img);
        result.outputs.push_back(dir / "range.npy");
        write_png_rgb8(dir / "range.png", width, height, range_image_rgb(img, width, height));
        result.outputs.push_back(dir / "range.png");
    }
    result.write_s = seconds_since(t0);
    return result;
}

}  // namespace beamtrace
