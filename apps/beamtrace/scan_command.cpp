#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "beamtrace/core/angle_text.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/vec3_text.hpp"
#include "beamtrace/pipeline/scan_job.hpp"
#include "commands.hpp"
#include "interrupt.hpp"
#include "progress_bar.hpp"

namespace beamtrace::cli {
namespace {

/// What `beamtrace scan` binds its options to: the library's ScanJobConfig and the sensor
/// options it applies (ScanJobConfig::apply), plus the CLI's own output switches.
struct ScanCommand {
    ScanJobConfig job;
    ScanSensorOptions sensor;
    bool quiet = false;
    bool progress = false;
    bool allow_empty = false;
};

/// Prints a warning when `rad`, from a radians option, is more than a full turn.
void warn_if_beyond_turn(double rad, const char* what) {
    if (const std::string w = radians_beyond_turn_warning(rad, what); !w.empty()) {
        std::fprintf(stderr, "beamtrace: warning: %s\n", w.c_str());
    }
}

double angle_rad(const std::string& text, const char* what) {
    const double v = parse_angle_option(text, what, AngleUnit::rad);
    warn_if_beyond_turn(v, what);
    return v;
}

int run(ScanCommand& cmd) {
    ScanJobConfig& c = cmd.job;
    c.apply(cmd.sensor);
    c.cancel = &interrupt_token();
    catch_interrupts();
    const ScanCommand& o = cmd;
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
        const auto rate = [&](double s) {
            return s > 0 ? static_cast<double>(r.rays) / s / 1e6 : 0.0;
        };
        std::printf(
            "time: load %.3f s, build (%s) %.3f s, trace %.3f s (%.2f M rays/s), write "
            "%.3f s (trace and write %.2f M rays/s)\n",
            r.load_s, std::string(to_string(c.backend)).c_str(), r.build_s, r.trace_s,
            rate(r.trace_s), r.write_s, rate(r.trace_s + r.write_s));
        for (const auto& p : r.outputs) {
            std::printf("wrote %s\n", p.string().c_str());
        }
        for (const auto& note : r.notes) {
            std::printf("%s\n", note.c_str());
        }
    }
    std::fflush(stdout);
    for (const auto& why : r.few_hits_reasons) {
        std::fprintf(stderr, "beamtrace: warning: %s\n", why.c_str());
    }
    if (r.hits == 0 && r.rays > 0 && !o.allow_empty) {
        std::fprintf(stderr,
                     "beamtrace: error: scan: no ray hit the scene (see above; the outputs are "
                     "written; --allow-empty accepts an empty result)\n");
        return 3;
    }
    return 0;
}

/// The image sensor's pose and field of view (the defaults are ImageSensorConfig's; the demo
/// scene brings its own sensor).
void add_sensor_options(CLI::App& app, ScanSensorOptions& sensor) {
    CLI::App* cmd = &app;
    cmd->add_option_function<std::string>(
        "--position",
        [&sensor](const std::string& s) { sensor.position_m = parse_vec3(s, "--position"); },
        "Sensor position x,y,z in metres");
    cmd->add_option_function<std::string>(
        "--orientation",
        [&sensor](const std::string& s) {
            const Vec3d rpy = parse_angle_vec3(s, "--orientation", AngleUnit::rad);
            for (int k = 0; k < 3; ++k) {
                warn_if_beyond_turn(rpy[k], "--orientation");
            }
            sensor.orientation_rad = rpy;
        },
        "Sensor roll,pitch,yaw in radians (each may carry its unit: 0,-90deg,0)");
    const ImageSensorConfig dflt_sensor;
    const auto dflt = [](auto v) {
        std::ostringstream s;
        s << " (default " << v << ")";
        return s.str();
    };
    cmd->add_option("--width", sensor.width, "Image width in pixels" + dflt(dflt_sensor.width));
    cmd->add_option("--height", sensor.height, "Image height in pixels" + dflt(dflt_sensor.height));
    cmd->add_option_function<std::string>(
        "--hfov", [&sensor](const std::string& s) { sensor.hfov_rad = angle_rad(s, "--hfov"); },
        "Horizontal field of view in radians, or with its unit (60deg)" +
            dflt(dflt_sensor.hfov_rad));
    cmd->add_option_function<std::string>(
        "--vfov", [&sensor](const std::string& s) { sensor.vfov_rad = angle_rad(s, "--vfov"); },
        "Vertical field of view in radians, or with its unit (45deg)" + dflt(dflt_sensor.vfov_rad));
}

}  // namespace

std::function<int()> add_scan_command(CLI::App& app) {
    auto cmd_state = std::make_shared<ScanCommand>();
    ScanJobConfig& job = cmd_state->job;
    ScanSensorOptions& sensor = cmd_state->sensor;
    CLI::App* cmd = app.add_subcommand(
        "scan",
        "Cast a sensor's rays into a triangle scene and write ranges, face IDs, points and "
        "range images");
    cmd->add_option("--mesh", job.meshes,
                    "Mesh file (OBJ, PLY, STL, glTF .gltf/.glb); repeat to concatenate")
        ->check(CLI::ExistingFile);
    cmd->add_flag("--demo", job.demo,
                  "Use the embedded demo scene (terrain, three vehicles, an occluding plane)");
    cmd->add_option_function<std::string>(
           "--pattern", [&job](const std::string& s) { job.pattern = parse_pattern_kind(s); },
           static_scan_pattern_choices())
        ->default_str(job.pattern);
    add_sensor_options(*cmd, sensor);
    cmd->add_option("--rays", job.rays_file, "Rays file for --pattern rays: CSV ox,oy,oz,dx,dy,dz")
        ->check(CLI::ExistingFile);
    cmd->add_option_function<std::string>(
           "--backend", [&job](const std::string& s) { job.backend = parse_backend_kind(s); },
           backend_choices())
        ->default_str(std::string(to_string(job.backend)));
    cmd->add_option_function<std::string>(
           "--kdtree-rules",
           [&job](const std::string& s) {
               try {
                   job.backend_config.kdtree = parse_kdtree_rules(s);
               } catch (const ConfigError& e) {
                   throw ConfigError(std::string("--kdtree-rules: ") + e.what());
               }
           },
           "k-d tree build: sah (binned SAH) or report (the ladar report's rules)")
        ->default_str("sah");
    cmd->add_option("--threads", job.threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    cmd->add_option("--output", job.output_dir, "Output directory")->required();
    cmd->add_option_function<std::string>(
        "--exclude-faces",
        [&job](const std::string& s) { job.exclude_faces = parse_face_ranges(s); },
        "Face IDs to leave out of points.ply, e.g. 5804-5805,12");
    cmd->add_flag("--allow-empty", cmd_state->allow_empty,
                  "Exit 0 even when no ray hits (else: the reasons, and exit 3)");
    cmd->add_option_function<std::string>(
           "--outputs",
           [&job](const std::string& s) {
               try {
                   job.outputs = parse_scan_outputs(s);
               } catch (const ConfigError& e) {
                   throw ConfigError(std::string("--outputs: ") + e.what());
               }
           },
           "Files to write, comma-separated: ply (points.ply), npy (range.npy), png (range.png), "
           "csv (hits.csv), laz (points.laz)")
        ->default_str(to_string(job.outputs));
    cmd->add_flag_callback(
        "--laz", [&job] { job.outputs.laz = true; },
        "Also write points.laz (the same as adding laz to --outputs)");
    cmd->add_flag("--quiet", cmd_state->quiet, "No progress bar and no summary");
    cmd->add_flag("--progress", cmd_state->progress,
                  "Show the progress bar even when not on a terminal");
    return [cmd_state] { return run(*cmd_state); };
}

}  // namespace beamtrace::cli
