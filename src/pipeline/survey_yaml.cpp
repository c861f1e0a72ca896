// Survey files in YAML (docs/survey.md): every problem is collected and reported at once.
#include <algorithm>
#include <fstream>
#include <numbers>
#include <sstream>

#include "beamtrace/io/point_sink_registry.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "pipeline/detail/physics_yaml.hpp"
#include "text/yaml_checker.hpp"

namespace beamtrace {
namespace {

using detail::YamlChecker;
constexpr double kDeg = std::numbers::pi / 180.0;

RollPitchYaw rpy_deg(const Vec3d& d) {
    return {d.x * kDeg, d.y * kDeg, d.z * kDeg};
}

void positive(YamlChecker& c, const YAML::Node& n, const std::string& key, double& out) {
    if (n && c.number(n, key, out) && !(out > 0)) {
        c.error(n, key, "must be positive");
    }
}

/// Each scanner type accepts its own keys only (a rotating scanner's scan_rate_hz is an error,
/// not silently ignored); an unknown type's keys are checked against all types'.
void check_scanner_keys(YamlChecker& c, const YAML::Node& n, const std::string& type) {
    if (type == "rotating") {
        c.only_keys(
            n, "scanner",
            {"type", "preset", "beam_elevations_deg", "rotation_rate_hz", "azimuth_resolution_deg",
             "spin_clockwise", "duration_s", "range_min_m", "range_max_m"},
            "a rotating scanner");
    } else if (type == "line") {
        c.only_keys(n, "scanner",
                    {"type", "pulse_rate_hz", "scan_rate_hz", "scan_angle_max_deg", "waveform",
                     "duration_s", "range_min_m", "range_max_m"},
                    "a line scanner");
    } else if (type == "pinhole" || type == "scan") {
        c.only_keys(n, "scanner",
                    {"type", "width", "height", "hfov_deg", "vfov_deg", "frames", "pulse_rate_hz",
                     "range_min_m", "range_max_m"},
                    "a " + type + " scanner");
    } else {
        c.only_keys(n, "scanner",
                    {"type", "preset", "beam_elevations_deg", "rotation_rate_hz",
                     "azimuth_resolution_deg", "spin_clockwise", "pulse_rate_hz", "scan_rate_hz",
                     "scan_angle_max_deg", "waveform", "width", "height", "hfov_deg", "vfov_deg",
                     "frames", "duration_s", "range_min_m", "range_max_m"});
    }
}

void parse_scanner(YamlChecker& c, const YAML::Node& n, SurveySpec& s) {
    if (!n || !n.IsMap()) {
        c.error(n ? n : YAML::Node(), "scanner", "expected a map with at least 'type'");
        return;
    }
    const std::string type = n["type"] && n["type"].IsScalar() ? n["type"].Scalar() : "";
    check_scanner_keys(c, n, type);
    double duration = 0.0;
    const bool has_duration =
        n["duration_s"] && c.number(n["duration_s"], "scanner.duration_s", duration);
    if (type == "rotating") {
        s.scanner = ScannerKind::rotating;
        if (const auto p = n["preset"]) {
            const std::string name = p.IsScalar() ? p.Scalar() : "";
            if (name == "vlp16") {
                s.rotating = vlp16();
            } else if (name == "hdl32") {
                s.rotating = hdl32();
            } else if (name == "hdl64") {
                s.rotating = hdl64();
            } else if (name == "os128") {
                s.rotating = os128();
            } else {
                c.error(p, "scanner.preset",
                        "unknown preset (expected vlp16, hdl32, hdl64, os128)");
            }
        }
        if (const auto b = n["beam_elevations_deg"]) {
            s.rotating.beam_elevations_deg.clear();
            if (!b.IsSequence() || b.size() == 0) {
                c.error(b, "scanner.beam_elevations_deg", "expected a list of angles");
            } else {
                for (std::size_t i = 0; i < b.size(); ++i) {
                    double e = 0;
                    if (c.number(b[i], "scanner.beam_elevations_deg[" + std::to_string(i) + "]",
                                 e)) {
                        s.rotating.beam_elevations_deg.push_back(e);
                    }
                }
            }
        }
        positive(c, n["rotation_rate_hz"], "scanner.rotation_rate_hz", s.rotating.rotation_rate_hz);
        positive(c, n["azimuth_resolution_deg"], "scanner.azimuth_resolution_deg",
                 s.rotating.azimuth_resolution_deg);
        if (const auto cw = n["spin_clockwise"]) {
            c.boolean(cw, "scanner.spin_clockwise", s.rotating.spin_clockwise);
        }
        if (has_duration) {
            s.rotating.duration_s = duration;
        }
        for (const auto& p : s.rotating.validate()) {
            c.error(n, "scanner", p);
        }
    } else if (type == "line") {
        s.scanner = ScannerKind::line;
        positive(c, n["pulse_rate_hz"], "scanner.pulse_rate_hz", s.line.pulse_rate_hz);
        positive(c, n["scan_rate_hz"], "scanner.scan_rate_hz", s.line.scan_rate_hz);
        positive(c, n["scan_angle_max_deg"], "scanner.scan_angle_max_deg",
                 s.line.scan_angle_max_deg);
        if (const auto w = n["waveform"]) {
            try {
                s.line.waveform = parse_scan_waveform(w.IsScalar() ? w.Scalar() : "");
            } catch (const ConfigError& e) {
                c.error(w, "scanner.waveform", e.what());
            }
        }
        if (has_duration) {
            s.line.duration_s = duration;
        }
        for (const auto& p : s.line.validate()) {
            c.error(n, "scanner", p);
        }
    } else if (type == "pinhole" || type == "scan") {
        s.scanner = ScannerKind::image;
        s.image.projection = type == "pinhole" ? ImageProjection::pinhole : ImageProjection::scan;
        long v = 0;
        if (n["width"] && c.integer(n["width"], "scanner.width", 1, 1 << 20, v)) {
            s.image.image.width = static_cast<int>(v);
        }
        if (n["height"] && c.integer(n["height"], "scanner.height", 1, 1 << 16, v)) {
            s.image.image.height = static_cast<int>(v);
        }
        if (n["frames"] && c.integer(n["frames"], "scanner.frames", 1, 1L << 30, v)) {
            s.image.frames = static_cast<std::uint64_t>(v);
        }
        double deg = 0;
        if (n["hfov_deg"] && c.number(n["hfov_deg"], "scanner.hfov_deg", deg)) {
            s.image.image.hfov_rad = deg * kDeg;
        }
        if (n["vfov_deg"] && c.number(n["vfov_deg"], "scanner.vfov_deg", deg)) {
            s.image.image.vfov_rad = deg * kDeg;
        }
        positive(c, n["pulse_rate_hz"], "scanner.pulse_rate_hz", s.image.pulse_rate_hz);
        for (const auto& p : s.image.validate()) {
            c.error(n, "scanner", p);
        }
    } else {
        c.error(n["type"] ? n["type"] : n, "scanner.type",
                "expected rotating, line, pinhole or scan");
    }
    if (n["range_min_m"] && c.number(n["range_min_m"], "scanner.range_min_m", s.range_min_m) &&
        s.range_min_m < 0) {
        c.error(n["range_min_m"], "scanner.range_min_m", "must not be negative");
    }
    positive(c, n["range_max_m"], "scanner.range_max_m", s.range_max_m);
    if (s.range_max_m <= s.range_min_m) {
        c.error(n, "scanner", "range_max_m must exceed range_min_m");
    }
}

void parse_platform(YamlChecker& c, const YAML::Node& n, SurveySpec& s) {
    if (!n || !n.IsMap()) {
        c.error(n ? n : YAML::Node(), "platform", "expected a map with at least 'type'");
        return;
    }
    c.only_keys(
        n, "platform",
        {"type", "position_m", "rotate_deg", "waypoints_m", "attitudes_deg", "speed_mps", "file"});
    const std::string type = n["type"] && n["type"].IsScalar() ? n["type"].Scalar() : "";
    if (type == "static") {
        s.platform = PlatformKind::fixed;
        if (n["position_m"]) {
            c.vec3(n["position_m"], "platform.position_m", s.fixed_pose.position_m);
        }
        Vec3d r;
        if (n["rotate_deg"] && c.vec3(n["rotate_deg"], "platform.rotate_deg", r)) {
            s.fixed_pose.attitude = Quat::from_rpy(rpy_deg(r));
        }
    } else if (type == "legs") {
        s.platform = PlatformKind::legs;
        const auto w = n["waypoints_m"];
        if (!w || !w.IsSequence() || w.size() < 2) {
            c.error(w ? w : n, "platform.waypoints_m", "expected a list of at least two [x, y, z]");
        } else {
            for (std::size_t i = 0; i < w.size(); ++i) {
                Vec3d p;
                if (c.vec3(w[i], "platform.waypoints_m[" + std::to_string(i) + "]", p)) {
                    s.legs.waypoints_m.push_back(p);
                }
            }
        }
        if (const auto a = n["attitudes_deg"]) {
            if (!a.IsSequence()) {
                c.error(a, "platform.attitudes_deg", "expected a list of [roll, pitch, yaw]");
            } else {
                for (std::size_t i = 0; i < a.size(); ++i) {
                    Vec3d r;
                    if (c.vec3(a[i], "platform.attitudes_deg[" + std::to_string(i) + "]", r)) {
                        s.legs.attitudes.push_back(rpy_deg(r));
                    }
                }
            }
        }
        positive(c, n["speed_mps"], "platform.speed_mps", s.legs.speed_mps);
        for (const auto& p : s.legs.validate()) {
            c.error(n, "platform", p);
        }
    } else if (type == "trajectory") {
        s.platform = PlatformKind::trajectory;
        const auto f = n["file"];
        if (!f || !f.IsScalar()) {
            c.error(f ? f : n, "platform.file", "expected a trajectory CSV file name");
        } else {
            s.trajectory_file = s.source.parent_path() / f.Scalar();
            if (!std::filesystem::exists(s.trajectory_file)) {
                c.error(f, "platform.file", "file not found: " + s.trajectory_file.string());
            }
        }
    } else {
        c.error(n["type"] ? n["type"] : n, "platform.type", "expected static, legs or trajectory");
    }
}

/// The `output:` block: the LAS point format, the trajectory rate, and one `<key>: true|false`
/// per switchable sink of the registry.
void parse_output(YamlChecker& c, const YAML::Node& o, SurveySpec& s) {
    std::vector<std::string> known{"point_format", "trajectory_rate_hz"};
    for (const SinkEntry& e : point_sinks()) {
        if (!e.key.empty()) {
            known.emplace_back(e.key);
        }
    }
    for (const auto& kv : o) {
        const auto name = kv.first.as<std::string>();
        if (std::find(known.begin(), known.end(), name) == known.end()) {
            std::string list;
            for (const auto& k : known) {
                list += (list.empty() ? "" : ", ") + k;
            }
            c.error(kv.first, "output." + name, "unknown key (expected one of: " + list + ")");
        }
    }
    long pf = 0;
    if (o["point_format"] && c.integer(o["point_format"], "output.point_format", 6, 8, pf)) {
        s.point_format = static_cast<int>(pf);
    }
    for (const SinkEntry& e : point_sinks()) {
        const std::string key(e.key);
        bool on = false;
        if (!key.empty() && o[key] && c.boolean(o[key], "output." + key, on)) {
            std::erase(s.outputs, std::string(e.name));
            if (on) {
                s.outputs.emplace_back(e.name);
            }
        }
    }
    if (o["trajectory_rate_hz"] &&
        c.number(o["trajectory_rate_hz"], "output.trajectory_rate_hz", s.trajectory_rate_hz) &&
        s.trajectory_rate_hz < 0) {
        c.error(o["trajectory_rate_hz"], "output.trajectory_rate_hz", "must not be negative");
    }
}

}  // namespace

SurveySpec parse_survey_spec(const std::string& yaml_text, const std::filesystem::path& source) {
    const YAML::Node root = detail::parse_yaml(yaml_text, source);
    if (!root.IsMap()) {
        throw ConfigError(source.string() + ": expected a map with scene, scanner, platform");
    }
    YamlChecker c(source);
    SurveySpec s;
    s.source = source;
    s.text = yaml_text;
    c.only_keys(root, "", {"scene", "scanner", "platform", "mount", "output", "physics"});
    if (const auto sc = root["scene"]) {
        if (!sc.IsScalar()) {
            c.error(sc, "scene", "expected a scene file name or 'demo'");
        } else if (sc.Scalar() != "demo") {
            s.scene_file = source.parent_path() / sc.Scalar();
            if (!std::filesystem::exists(s.scene_file)) {
                c.error(sc, "scene", "file not found: " + s.scene_file.string());
            }
        }
    } else {
        c.error(root, "scene", "missing (a scene file name, or 'demo')");
    }
    parse_scanner(c, root["scanner"], s);
    parse_platform(c, root["platform"], s);
    if (const auto m = root["mount"]) {
        c.only_keys(m, "mount", {"lever_arm_m", "boresight_deg"});
        Vec3d arm, bore;
        if (m["lever_arm_m"]) {
            c.vec3(m["lever_arm_m"], "mount.lever_arm_m", arm);
        }
        if (m["boresight_deg"]) {
            c.vec3(m["boresight_deg"], "mount.boresight_deg", bore);
        }
        s.mount = Mount::from_lever_arm(arm, rpy_deg(bore));
    }
    if (const auto o = root["output"]) {
        parse_output(c, o, s);
    }
    if (const auto ph = root["physics"]) {
        s.physics.emplace();
        detail::parse_physics_block(c, ph, *s.physics);
    }
    c.throw_if_any("survey file");
    return s;
}

SurveySpec load_survey_spec(const std::filesystem::path& path) {
    return parse_survey_spec(detail::read_config_text(path, "survey file"), path);
}

}  // namespace beamtrace
