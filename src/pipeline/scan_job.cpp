#include "beamtrace/pipeline/scan_job.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/name_table.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/sensor/rays_file.hpp"
#include "pipeline/detail/scan_writer.hpp"
#include "pipeline/detail/survey_diagnosis.hpp"

namespace beamtrace {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr std::size_t kTraceChunk = std::size_t{1} << 16;
static_assert(kTraceChunk % detail::kScanPieceRays == 0);

/// The outputs of ScanOutputs by name, in the order they are listed and written.
struct ScanOutputName {
    std::string_view name;
    bool ScanOutputs::*on;
};
constexpr std::array<ScanOutputName, 5> kScanOutputs{{{"ply", &ScanOutputs::ply},
                                                      {"npy", &ScanOutputs::npy},
                                                      {"png", &ScanOutputs::png},
                                                      {"csv", &ScanOutputs::csv},
                                                      {"laz", &ScanOutputs::laz}}};

std::string scan_output_names(std::string_view separator, std::string_view last) {
    std::string out;
    for (std::size_t k = 0; k < kScanOutputs.size(); ++k) {
        out += k == 0 ? "" : (k + 1 == kScanOutputs.size() ? last : separator);
        out += kScanOutputs[k].name;
    }
    return out;
}

/// The scan's rays, and the range image's width x height (0 x 0: none).
RayBatch cast_scan_rays(const ScanJobConfig& config, int& width, int& height) {
    StaticRays cast =
        static_scan_pattern(config.pattern).static_rays({config.sensor, config.rays_file});
    if (!cast.grid && config.image_width) {
        cast.grid = ImageGrid{*config.image_width, *config.image_height};
        if (static_cast<std::size_t>(cast.grid->width) *
                static_cast<std::size_t>(cast.grid->height) !=
            cast.rays.size()) {
            throw ConfigError(
                config.rays_file.string() + ": has " + std::to_string(cast.rays.size()) +
                " rays but --width x --height is " + std::to_string(cast.grid->width) + " x " +
                std::to_string(cast.grid->height));
        }
    }
    width = cast.grid ? cast.grid->width : 0;
    height = cast.grid ? cast.grid->height : 0;
    return std::move(cast.rays);
}

}  // namespace

ScanOutputs parse_scan_outputs(std::string_view list) {
    const std::string expected =
        " (expected a comma-separated list of " + scan_output_names(", ", " and ") + ")";
    ScanOutputs o{false, false, false, false, false};
    bool any = false;
    while (true) {
        const std::size_t comma = std::min(list.find(','), list.size());
        const std::string_view item = list.substr(0, comma);
        const auto* e = std::find_if(kScanOutputs.begin(), kScanOutputs.end(),
                                     [&](const ScanOutputName& n) { return n.name == item; });
        if (item.empty()) {
            throw ConfigError("empty output name" + expected);
        }
        if (e == kScanOutputs.end()) {
            throw ConfigError("unknown output '" + std::string(item) + "'" + expected);
        }
        if (o.*(e->on)) {
            throw ConfigError("output '" + std::string(item) + "' is listed twice");
        }
        o.*(e->on) = any = true;
        if (comma == list.size()) {
            break;
        }
        list.remove_prefix(comma + 1);
    }
    return o;
}

std::string to_string(const ScanOutputs& outputs) {
    std::string out;
    for (const ScanOutputName& n : kScanOutputs) {
        if (outputs.*(n.on)) {
            out += (out.empty() ? "" : ",") + std::string(n.name);
        }
    }
    return out;
}

std::string scan_output_choices() {
    return scan_output_names(", ", ", ");
}

std::string parse_pattern_kind(std::string_view name) {
    return std::string(static_scan_pattern(name).name);
}

KdTreeBuildConfig parse_kdtree_rules(std::string_view name) {
    static constexpr NameTable<KdSplitRule, 2> kRules{
        "k-d tree rule set", {{{KdSplitRule::sah, "sah"}, {KdSplitRule::report, "report"}}}};
    return kRules.parse(name) == KdSplitRule::report ? KdTreeBuildConfig::report()
                                                     : KdTreeBuildConfig{};
}

void ScanJobConfig::apply(const ScanSensorOptions& o) {
    if (demo) {
        sensor = demo_sensor();
    }
    sensor.position_m = o.position_m.value_or(sensor.position_m);
    if (o.orientation_rad) {
        sensor.orientation = {o.orientation_rad->x, o.orientation_rad->y, o.orientation_rad->z};
    }
    if (reads_rays_file()) {
        image_width = o.width;
        image_height = o.height;
    } else {
        sensor.width = o.width.value_or(sensor.width);
        sensor.height = o.height.value_or(sensor.height);
    }
    sensor.hfov_rad = o.hfov_rad.value_or(sensor.hfov_rad);
    sensor.vfov_rad = o.vfov_rad.value_or(sensor.vfov_rad);
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
    if (to_string(outputs).empty()) {
        p.emplace_back("no output selected (--outputs: " + scan_output_choices() + ")");
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

ScanWritten write_scan_outputs(const ScanJobConfig& config, const RayBatch& rays,
                               const HitBatch& hits, int width, int height, ThreadPool& pool) {
    detail::ScanStream stream(config, rays, hits, width, height, pool);
    for (std::size_t b = 0; b < rays.size(); b += kTraceChunk) {
        throw_if_cancelled(config.cancel, "scan");
        stream.add(b, std::min(rays.size(), b + kTraceChunk));
    }
    return stream.finish();
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
    throw_if_cancelled(config.cancel, "scan");
    ScanResult result;
    ThreadPool pool(config.threads);

    // Inputs first: nothing is written before they all parse.
    auto t0 = Clock::now();
    Scene scene = config.demo ? make_demo_scene() : load_scene_meshes(config.meshes);
    int width = 0, height = 0;
    const RayBatch rays = cast_scan_rays(config, width, height);
    result.load_s = seconds_since(t0);
    result.triangles = scene.triangle_count();
    result.parts = scene.parts;
    result.rays = rays.size();

    t0 = Clock::now();
    const auto backend = make_backend(config.backend, scene.geometry, pool, config.backend_config);
    result.build_s = seconds_since(t0);

    // The outputs are written as the rays are traced: each chunk's records and image columns
    // between its trace and the next chunk's. trace_s counts the trace alone (as before the
    // writing overlapped it), write_s the rest from the first file made to the last renamed.
    t0 = Clock::now();
    const Clock::time_point start = t0;
    HitBatch hits;
    hits.resize(rays.size());
    if (progress) {
        progress(0, rays.size());  // the trace starts: rates count from here
    }
    result.trace_s = seconds_since(t0);
    detail::ScanStream stream(config, rays, hits, width, height, pool);
    for (std::size_t b = 0; b < rays.size(); b += kTraceChunk) {
        t0 = Clock::now();
        throw_if_cancelled(config.cancel, "scan");
        const std::size_t e = std::min(rays.size(), b + kTraceChunk);
        backend->intersect(rays, b, e, hits, pool);
        if (progress) {
            progress(e, rays.size());
        }
        result.trace_s += seconds_since(t0);
        stream.add(b, e);
    }
    ScanWritten written = stream.finish();
    result.write_s = seconds_since(start) - result.trace_s;
    result.hits = written.hits;
    result.points_written = written.points_written;
    result.outputs = std::move(written.outputs);
    result.notes = std::move(written.notes);
    result.few_hits_reasons = detail::diagnose_scan(rays, result.hits, scene.geometry.bounds());
    return result;
}

}  // namespace beamtrace
