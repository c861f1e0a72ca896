#include <charconv>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"
#include "beamtrace/pipeline/scan_job.hpp"
#include "commands.hpp"
#include "progress_bar.hpp"

namespace beamtrace::cli {
namespace {

/// Parses "a,b,c" into three doubles; throws ConfigError naming the option.
Vec3d parse_triple(const std::string& text, const char* option) {
    Vec3d v;
    std::size_t start = 0;
    for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t comma = text.find(',', start);
        if ((k < 2) != (comma != std::string::npos)) {
            throw ConfigError(std::string(option) +
                              " expects three comma-separated numbers, got '" + text + "'");
        }
        const std::string item =
            text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        double x = 0;
        const auto* b = item.data();
        const auto* e = item.data() + item.size();
        while (b < e && *b == ' ') {
            ++b;
        }
        const auto [ptr, ec] = std::from_chars(b, e, x);
        if (ec != std::errc() || ptr != e || b == e) {
            throw ConfigError(std::string(option) + ": '" + item + "' is not a number");
        }
        v[k] = x;
        start = comma + 1;
    }
    return v;
}

struct ScanOptions {
    std::vector<std::string> meshes;
    bool demo = false;
    std::string pattern = "pinhole";
    std::string position, orientation;
    std::optional<int> width, height;
    std::optional<double> hfov, vfov;
    std::string rays;
    std::string backend{to_string(default_backend_kind())};
    std::string kdtree_rules = "sah";
    unsigned threads = 0;
    std::string output;
    std::string exclude_faces;
    bool quiet = false;
    bool progress = false;
};

int run(const ScanOptions& o) {
    ScanJobConfig c;
    for (const auto& m : o.meshes) {
        c.meshes.emplace_back(m);
    }
    c.demo = o.demo;
    c.pattern = parse_pattern_kind(o.pattern);
    c.backend = parse_backend_kind(o.backend);
    if (o.kdtree_rules == "report") {
        c.backend_config.kdtree = KdTreeBuildConfig::report();
    } else if (o.kdtree_rules != "sah") {
        throw ConfigError("--kdtree-rules: expected sah or report, got '" + o.kdtree_rules + "'");
    }
    c.threads = o.threads;
    c.output_dir = o.output;
    c.rays_file = o.rays;
    c.exclude_faces = parse_face_ranges(o.exclude_faces);
    if (c.demo) {
        c.sensor = demo_sensor();
    }
    if (!o.position.empty()) {
        c.sensor.position_m = parse_triple(o.position, "--position");
    }
    if (!o.orientation.empty()) {
        const Vec3d rpy = parse_triple(o.orientation, "--orientation");
        c.sensor.orientation = {rpy.x, rpy.y, rpy.z};
    }
    if (c.reads_rays_file()) {
        c.image_width = o.width;
        c.image_height = o.height;
    } else {
        c.sensor.width = o.width.value_or(c.sensor.width);
        c.sensor.height = o.height.value_or(c.sensor.height);
    }
    c.sensor.hfov_rad = o.hfov.value_or(c.sensor.hfov_rad);
    c.sensor.vfov_rad = o.vfov.value_or(c.sensor.vfov_rad);

    ProgressBar bar("tracing", !o.quiet && (o.progress || stderr_is_terminal()));
    const ScanResult r =
        run_scan(c, [&](std::size_t done, std::size_t total) { bar.update(done, total); });
    bar.finish();
    if (!o.quiet) {
        std::printf("scene: %zu triangles in %zu part(s)\n", r.triangles, r.parts.size());
        for (const auto& p : r.parts) {
            std::printf("  faces %u-%u: %s\n", p.first_face,
                        p.face_count ? p.first_face + p.face_count - 1 : p.first_face,
                        p.name.c_str());
        }
        std::printf("rays: %zu, hits: %zu, points written: %zu\n", r.rays, r.hits,
                    r.points_written);
        std::printf(
            "time: load %.3f s, build (%s) %.3f s, trace %.3f s (%.2f M rays/s), write %.3f s\n",
            r.load_s, std::string(to_string(c.backend)).c_str(), r.build_s, r.trace_s,
            r.trace_s > 0 ? static_cast<double>(r.rays) / r.trace_s / 1e6 : 0.0, r.write_s);
        for (const auto& p : r.outputs) {
            std::printf("wrote %s\n", p.string().c_str());
        }
    }
    return 0;
}

}  // namespace

std::function<int()> add_scan_command(CLI::App& app) {
    auto opts = std::make_shared<ScanOptions>();
    CLI::App* cmd = app.add_subcommand(
        "scan",
        "Cast a sensor's rays into a triangle scene and write ranges, face IDs, points and "
        "range images");
    cmd->add_option("--mesh", opts->meshes, "Mesh file (OBJ, PLY, STL); repeat to concatenate")
        ->check(CLI::ExistingFile);
    cmd->add_flag("--demo", opts->demo,
                  "Use the embedded demo scene (terrain, three vehicles, an occluding plane)");
    cmd->add_option("--pattern", opts->pattern, "pinhole | scan | rays")->capture_default_str();
    cmd->add_option("--position", opts->position, "Sensor position x,y,z in metres");
    cmd->add_option("--orientation", opts->orientation, "Sensor roll,pitch,yaw in radians");
    // The defaults are ImageSensorConfig's (the demo scene brings its own sensor).
    const ImageSensorConfig sensor;
    const auto dflt = [](auto v) {
        std::ostringstream s;
        s << " (default " << v << ")";
        return s.str();
    };
    cmd->add_option("--width", opts->width, "Image width in pixels" + dflt(sensor.width));
    cmd->add_option("--height", opts->height, "Image height in pixels" + dflt(sensor.height));
    cmd->add_option("--hfov", opts->hfov,
                    "Horizontal field of view in radians" + dflt(sensor.hfov_rad));
    cmd->add_option("--vfov", opts->vfov,
                    "Vertical field of view in radians" + dflt(sensor.vfov_rad));
    cmd->add_option("--rays", opts->rays, "Rays file for --pattern rays: CSV ox,oy,oz,dx,dy,dz")
        ->check(CLI::ExistingFile);
    cmd->add_option("--backend", opts->backend, backend_choices())->capture_default_str();
    cmd->add_option("--kdtree-rules", opts->kdtree_rules,
                    "k-d tree build: sah (binned SAH) or report (the ladar report's rules)")
        ->capture_default_str();
    cmd->add_option("--threads", opts->threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    cmd->add_option("--output", opts->output, "Output directory")->required();
    cmd->add_option("--exclude-faces", opts->exclude_faces,
                    "Face IDs to leave out of points.ply, e.g. 5804-5805,12");
    cmd->add_flag("--quiet", opts->quiet, "No progress bar and no summary");
    cmd->add_flag("--progress", opts->progress,
                  "Show the progress bar even when not on a terminal");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
