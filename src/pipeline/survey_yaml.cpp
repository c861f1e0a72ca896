// Survey files in YAML (docs/survey.md): every problem is collected and reported at once.
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <numbers>
#include <span>

#include "beamtrace/io/point_sink_registry.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/sensor/scan_pattern_registry.hpp"
#include "pipeline/detail/physics_yaml.hpp"
#include "pipeline/detail/weather_yaml.hpp"
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
/// not silently ignored), plus the survey's type and range limits (and `more`: an entry of
/// `scanners:` has its mount and channel).
void check_scanner_keys(YamlChecker& c, const YAML::Node& n, const std::string& key,
                        const ScanPatternEntry& type, std::span<const std::string_view> more) {
    std::vector<std::string_view> known{"type"};
    known.insert(known.end(), type.keys.begin(), type.keys.end());
    known.insert(known.end(), {"range_min_m", "range_max_m"});
    known.insert(known.end(), more.begin(), more.end());
    c.only_keys_of(n, key, known, "a " + std::string(type.name) + " scanner");
}

/// The type's own keys, through its registry entry (scan_pattern_registry.hpp).
void parse_scanner_type(YamlChecker& c, const YAML::Node& n, const std::string& key,
                        std::span<const std::string_view> more, ScannerSpec& out) {
    const std::string type = n["type"] && n["type"].IsScalar() ? n["type"].Scalar() : "";
    const ScanPatternEntry* entry = find_scan_pattern(type);
    if (entry == nullptr || entry->parse == nullptr) {
        c.error(n["type"] ? n["type"] : n, key + ".type", "expected " + survey_scanner_types());
        return;
    }
    check_scanner_keys(c, n, key, *entry, more);
    out = ScannerSpec(type, entry->parse(c, n));
}

/// A scanner block named `key` (`scanner:`, or an entry of `scanners:` with the `more` keys):
/// its type's settings and its range gate (a data-sheet preset's limits by default).
void parse_scanner_block(YamlChecker& c, const YAML::Node& n, const std::string& key,
                         std::span<const std::string_view> more, ScannerSpec& scanner,
                         double& range_min_m, double& range_max_m) {
    if (!n || !n.IsMap()) {
        c.error(n ? n : YAML::Node(), key, "expected a map with at least 'type'");
        return;
    }
    parse_scanner_type(c, n, key, more, scanner);
    if (const auto range = scanner.settings().preset_range_m()) {  // a data-sheet preset's
        range_min_m = range->first;
        range_max_m = range->second;
    }
    if (n["range_min_m"] && c.number(n["range_min_m"], key + ".range_min_m", range_min_m) &&
        range_min_m < 0) {
        c.error(n["range_min_m"], key + ".range_min_m", "must not be negative");
    }
    positive(c, n["range_max_m"], key + ".range_max_m", range_max_m);
    if (range_max_m <= range_min_m) {
        c.error(n, key, "range_max_m must exceed range_min_m");
    }
}

void parse_scanner(YamlChecker& c, const YAML::Node& n, SurveySpec& s) {
    parse_scanner_block(c, n, "scanner", {}, s.scanner, s.range_min_m, s.range_max_m);
}

void parse_platform(YamlChecker& c, const YAML::Node& n, SurveySpec& s) {
    if (!n || !n.IsMap()) {
        c.error(n ? n : YAML::Node(), "platform", "expected a map with at least 'type'");
        return;
    }
    c.only_keys(n, "platform",
                {"type", "position_m", "rotate_deg", "waypoints_m", "attitudes_deg", "speed_mps",
                 "file", "legs"});
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
        if (n["legs"]) {
            c.error(n["legs"], "platform.legs", "only with type: legs");
        }
        s.platform = PlatformKind::trajectory;
        const auto f = n["file"];
        if (!f || !f.IsScalar()) {
            c.error(f ? f : n, "platform.file", "expected a trajectory CSV file name");
        } else {
            s.trajectory_file = s.source.parent_path() / f.Scalar();
            c.existing_file(f, "platform.file", s.trajectory_file);
        }
    } else {
        c.error(n["type"] ? n["type"] : n, "platform.type", "expected static, legs or trajectory");
    }
}

/// One leg's `scanner:` overrides: `active` and the survey scanner type's own keys (not
/// duration_s: the leg's flight time sets it). The survey's keys the leg does not override are
/// added to the leg's map (the values keep their lines for the type's errors), the type's parse
/// reads the whole (it reads its own keys only, so `active` stays), and they are removed again:
/// with `scanners:` the same leg map is read once per scanner, each adding its own.
void parse_leg_scanner(YamlChecker& c, YAML::Node n, const YAML::Node& scanner,
                       const std::string& key, LegScanner& leg, const ScannerSpec& survey) {
    const ScanPatternEntry* entry = find_scan_pattern(survey.type());
    if (!n.IsMap() || entry == nullptr || entry->parse == nullptr) {
        c.error(n, key, "expected a map (active and the scanner's own keys)");
        return;
    }
    std::vector<std::string_view> known{"active"};
    std::copy_if(entry->keys.begin(), entry->keys.end(), std::back_inserter(known),
                 [](std::string_view k) { return k != "duration_s"; });
    c.only_keys_of(n, key, known, "a leg of a " + survey.type() + " scanner");
    const bool has_active = static_cast<bool>(n["active"]);
    if (has_active) {
        c.boolean(n["active"], key + ".active", leg.active);
    }
    if (!leg.active || n.size() == (has_active ? 1u : 0u)) {
        return;
    }
    std::vector<std::string> added;
    for (const auto& kv : scanner) {
        const std::string k = kv.first.IsScalar() ? kv.first.Scalar() : "";
        if (!n[k] && k != "range_min_m" && k != "range_max_m" && k != "duration_s" &&
            k != "mount" && k != "channel") {
            n[k] = kv.second;
            added.push_back(k);
        }
    }
    leg.scanner = ScannerSpec(survey.type(), entry->parse(c, n));
    for (const std::string& k : added) {  // the next scanner of `scanners:` adds its own
        n.remove(k);
    }
}

/// The leg's scanner as it fires for the leg's flight time: every problem of its timing (a
/// leg too short for one pulse) at the leg.
void check_leg_timing(YamlChecker& c, const YAML::Node& n, const std::string& key,
                      const LegScanner& leg, const ScannerSpec& survey, double start_s,
                      double end_s) {
    const ScannerSpec& own = leg.scanner ? *leg.scanner : survey;
    const auto timed = own.settings().with_timing(start_s, end_s - start_s);
    if (!timed) {
        c.error(n, key, "a " + own.type() + " scanner cannot fire for a leg's flight time");
        return;
    }
    for (const std::string& p : timed->validate()) {
        c.error(n, key, p);
    }
}

/// `platform.legs`: one entry per leg (waypoint k to k + 1), each `{}` or `{scanner: {...}}`,
/// for the survey's scanner `survey` (its block `scanner`, named `scanner_key`) into `out`.
void parse_leg_scanners(YamlChecker& c, const YAML::Node& legs, const YAML::Node& scanner,
                        const std::string& scanner_key, const ScannerSpec& survey,
                        std::vector<LegScanner>& out, const SurveySpec& s) {
    const std::size_t count = s.legs.waypoints_m.size() - 1;
    if (!legs.IsSequence() || legs.size() != count) {
        c.error(legs, "platform.legs",
                "expected a list of " + std::to_string(count) +
                    " legs (one per pair of consecutive waypoints), each {} or {scanner: {...}}");
        return;
    }
    if (scanner && scanner.IsMap() && scanner["duration_s"]) {
        c.error(scanner["duration_s"], scanner_key + ".duration_s",
                "not with platform.legs: each leg's scanner fires for the leg's flight time");
    }
    const std::vector<std::string> path_problems = s.legs.validate();
    std::vector<double> times;
    if (path_problems.empty()) {
        times = LinearLegs(s.legs).waypoint_times_s();
    }
    for (std::size_t l = 0; l < count; ++l) {
        const std::string key = "platform.legs[" + std::to_string(l) + "]";
        const YAML::Node item = legs[l];
        LegScanner& leg = out.emplace_back();
        if (!item.IsNull() && !item.IsMap()) {
            c.error(item, key, "expected a map ({} or {scanner: {...}})");
            continue;
        }
        c.only_keys(item, key, {"scanner"});
        const std::size_t errors = c.errors().size();
        if (item.IsMap() && item["scanner"]) {
            parse_leg_scanner(c, item["scanner"], scanner, key + ".scanner", leg, survey);
        }
        // The timing of settings already found wrong would repeat their errors.
        if (leg.active && !times.empty() && c.errors().size() == errors) {
            check_leg_timing(c, item, key, leg, survey, times[l], times[l + 1]);
        }
    }
}

/// The `mount:` block: the scanner's lever arm and boresight on the platform (an empty block,
/// null in YAML, keeps the defaults).
void parse_mount(YamlChecker& c, const YAML::Node& m, const std::string& key, Mount& out) {
    if (m.IsNull()) {
        return;
    }
    if (!m.IsMap()) {
        c.error(m, key, "expected a map with lever_arm_m, boresight_deg");
        return;
    }
    c.only_keys(m, key, {"lever_arm_m", "boresight_deg"});
    Vec3d arm, bore;
    if (m["lever_arm_m"]) {
        c.vec3(m["lever_arm_m"], key + ".lever_arm_m", arm);
    }
    if (m["boresight_deg"]) {
        c.vec3(m["boresight_deg"], key + ".boresight_deg", bore);
    }
    out = Mount::from_lever_arm(arm, rpy_deg(bore));
}

/// An entry of `scanners:`: a scanner block with its own `mount:` and `channel:`.
void parse_scanner_entry(YamlChecker& c, const YAML::Node& n, std::size_t i, SurveyScanner& out) {
    static constexpr std::string_view kMore[] = {"mount", "channel"};
    const std::string key = "scanners[" + std::to_string(i) + "]";
    parse_scanner_block(c, n, key, kMore, out.scanner, out.range_min_m, out.range_max_m);
    if (!n || !n.IsMap()) {
        return;
    }
    if (n["mount"]) {
        parse_mount(c, n["mount"], key + ".mount", out.mount);
    }
    long channel = static_cast<long>(i);
    if (n["channel"]) {
        c.integer(n["channel"], key + ".channel", 0, 3, channel);
    }
    out.channel = static_cast<std::uint8_t>(channel);
}

/// `scanners:`: 1 to 4 scanners, each on its own LAS scanner channel. The first one's settings
/// also fill the survey's single-scanner fields (SurveySpec::scanners).
void parse_scanners(YamlChecker& c, const YAML::Node& list, SurveySpec& s) {
    if (!list.IsSequence() || list.size() == 0 || list.size() > kMaxSurveyScanners) {
        c.error(list, "scanners",
                "expected a list of 1 to 4 scanners (LAS scanner channels 0-3), each a scanner "
                "block with its own mount: and channel:");
        return;
    }
    std::array<bool, kMaxSurveyScanners> used{};
    for (std::size_t i = 0; i < list.size(); ++i) {
        SurveyScanner& sc = s.scanners.emplace_back();
        parse_scanner_entry(c, list[i], i, sc);
        if (used[sc.channel]) {
            const YAML::Node at =
                list[i].IsMap() && list[i]["channel"] ? list[i]["channel"] : list[i];
            c.error(at, "scanners[" + std::to_string(i) + "].channel",
                    "channel " + std::to_string(sc.channel) +
                        " is already another scanner's (each scanner needs its own, 0-3)");
        }
        used[sc.channel] = true;
    }
    s.scanner = s.scanners.front().scanner;
    s.mount = s.scanners.front().mount;
    s.range_min_m = s.scanners.front().range_min_m;
    s.range_max_m = s.scanners.front().range_max_m;
}

/// The scanner(s): `scanner:` with `mount:`, or `scanners:` (each with its mount), not both.
void parse_scanner_blocks(YamlChecker& c, const YAML::Node& root, SurveySpec& s) {
    if (const auto list = root["scanners"]) {
        if (root["scanner"]) {
            c.error(list, "scanners",
                    "not with scanner: (one scanner: with mount:, or a scanners: list whose "
                    "entries each have their mount:)");
        }
        if (root["mount"]) {
            c.error(root["mount"], "mount",
                    "not with scanners: (each entry of scanners: has its own mount:)");
        }
        parse_scanners(c, list, s);
        return;
    }
    parse_scanner(c, root["scanner"], s);
    if (const auto m = root["mount"]) {
        parse_mount(c, m, "mount", s.mount);
    }
}

/// `platform.legs` for the scanner, or for each of `scanners:` (a leg's overrides apply to
/// every scanner).
void parse_legs_of_scanners(YamlChecker& c, const YAML::Node& root, SurveySpec& s) {
    const YAML::Node legs = root["platform"]["legs"];
    if (s.scanners.empty()) {
        parse_leg_scanners(c, legs, root["scanner"], "scanner", s.scanner, s.leg_scanners, s);
        return;
    }
    for (std::size_t i = 0; i < s.scanners.size(); ++i) {
        SurveyScanner& sc = s.scanners[i];
        const std::size_t errors = c.errors().size();
        parse_leg_scanners(c, legs, root["scanners"][i], "scanners[" + std::to_string(i) + "]",
                           sc.scanner, sc.leg_scanners, s);
        if (sc.leg_scanners.empty() && c.errors().size() > errors) {
            break;  // the list itself is wrong: once is enough
        }
    }
    s.leg_scanners = s.scanners.front().leg_scanners;
}

/// output.extra_bytes: a list of point attribute names (io/point_attributes.hpp), each at most
/// once.
void parse_extra_bytes(YamlChecker& c, const YAML::Node& x, SurveySpec& s) {
    const std::string key = "output.extra_bytes";
    if (!x.IsSequence()) {
        c.error(x, key, "expected a list of names (" + point_attribute_keys() + ")");
        return;
    }
    for (const YAML::Node& item : x) {
        const std::optional<PointAttribute> a =
            item.IsScalar() ? point_attribute_named(item.Scalar()) : std::nullopt;
        if (!a) {
            c.error(item, key,
                    (item.IsScalar() ? "unknown name '" + item.Scalar() + "'" : "not a name") +
                        "; expected one of " + point_attribute_keys());
        } else if (std::find(s.extra_bytes.begin(), s.extra_bytes.end(), *a) !=
                   s.extra_bytes.end()) {
            c.error(item, key, "'" + item.Scalar() + "' is listed twice");
        } else {
            s.extra_bytes.push_back(*a);
        }
    }
}

/// The `output:` block: the LAS point format, the trajectory rate, and one `<key>: true|false`
/// per switchable sink of the registry (an empty block, null in YAML, keeps the defaults).
void parse_output(YamlChecker& c, const YAML::Node& o, SurveySpec& s) {
    if (o.IsNull()) {
        return;
    }
    if (!o.IsMap()) {
        c.error(o, "output",
                "expected a map (point_format, trajectory_rate_hz, a switch per sink)");
        return;
    }
    std::vector<std::string> known{"point_format", "trajectory_rate_hz", "wave_packets",
                                   "extra_bytes", "point_source_id"};
    for (const SinkEntry& e : point_sinks()) {
        if (!e.key.empty()) {
            known.emplace_back(e.key);
        }
    }
    c.only_keys_of(o, "output", known);
    long pf = 0;
    if (o["point_format"] && c.integer(o["point_format"], "output.point_format", 4, 10, pf)) {
        if (pf == 4 || pf == 5) {
            c.error(o["point_format"], "output.point_format",
                    "the legacy wave packet formats 4 and 5 are not written; use 9 (format 6 + "
                    "wave packets) or 10 (format 8 + wave packets)");
        }
        s.point_format = static_cast<int>(pf);
    }
    if (const auto w = o["wave_packets"]) {
        const std::string v = w.IsScalar() ? w.Scalar() : "";
        if (v == "wdp" || v == "evlr") {
            s.wave_packets =
                v == "wdp" ? LasWaveformStorage::external : LasWaveformStorage::internal;
        } else {
            c.error(w, "output.wave_packets",
                    "expected wdp (points.wdp) or evlr (inside points.las)");
        }
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
    if (const auto x = o["extra_bytes"]) {
        parse_extra_bytes(c, x, s);
    }
    if (const auto id = o["point_source_id"]) {
        const std::string v = id.IsScalar() ? id.Scalar() : "";
        if (v == "part" || v == "leg" || v == "scanner") {
            s.point_source_id = v == "part"  ? PointSourceId::part
                                : v == "leg" ? PointSourceId::leg
                                             : PointSourceId::scanner;
        } else {
            c.error(id, "output.point_source_id", "expected part, leg or scanner");
        }
    }
    if (o["trajectory_rate_hz"] &&
        c.number(o["trajectory_rate_hz"], "output.trajectory_rate_hz", s.trajectory_rate_hz) &&
        s.trajectory_rate_hz < 0) {
        c.error(o["trajectory_rate_hz"], "output.trajectory_rate_hz", "must not be negative");
    }
}

/// physics.waveform.keep writes the wave packet twin of the point format (6 -> 9, 7 and 8 -> 10);
/// formats 9 and 10 need it, and whole picoseconds per bin (the descriptor's spacing).
void resolve_point_format(YamlChecker& c, const YAML::Node& root, SurveySpec& s) {
    const bool keep = s.physics && s.physics->keep_waveform;
    const YAML::Node at = root["output"] && root["output"].IsMap() && root["output"]["point_format"]
                              ? root["output"]["point_format"]
                              : root;
    if (!keep) {
        if (las_format_has_wave_packet(s.point_format)) {
            c.error(at, "output.point_format",
                    std::to_string(s.point_format) +
                        " has wave packets: it needs physics.waveform.keep: true");
        }
        return;
    }
    if (s.point_format >= 6 && s.point_format <= 8) {
        s.point_format = s.point_format == 6 ? 9 : 10;
    }
    const double ps = s.physics->waveform.bin_ns * 1000.0;
    if (std::abs(ps - std::round(ps)) > 1e-6 || ps < 1) {
        c.error(root["physics"], "physics.waveform.bin_ns",
                "must be a whole number of picoseconds for the LAS wave packets (keep: true)");
    }
}

/// points.laz holds no wave packets (LAZ formats 9 and 10 are not written): `laz: true` with
/// physics.waveform.keep is refused.
void check_laz(YamlChecker& c, const YAML::Node& root, const SurveySpec& s) {
    const bool laz = std::find(s.outputs.begin(), s.outputs.end(), "laz") != s.outputs.end();
    if (laz && las_format_has_wave_packet(s.point_format)) {
        c.error(root["output"]["laz"], "output.laz",
                "not with physics.waveform.keep: true (the wave packets of point format " +
                    std::to_string(s.point_format) +
                    " are written to points.las only; set laz: false)");
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
    c.only_keys(
        root, "",
        {"scene", "scanner", "scanners", "platform", "mount", "output", "physics", "weather"});
    if (const auto sc = root["scene"]) {
        if (!sc.IsScalar()) {
            c.error(sc, "scene", "expected a scene file name or 'demo'");
        } else if (sc.Scalar() != "demo") {
            s.scene_file = source.parent_path() / sc.Scalar();
            c.existing_file(sc, "scene", s.scene_file);
        }
    } else {
        c.error(root, "scene", "missing (a scene file name, or 'demo')");
    }
    parse_scanner_blocks(c, root, s);
    parse_platform(c, root["platform"], s);
    if (s.platform == PlatformKind::legs && root["platform"]["legs"] &&
        s.legs.waypoints_m.size() >= 2) {
        parse_legs_of_scanners(c, root, s);
    }
    if (const auto o = root["output"]) {
        parse_output(c, o, s);
    }
    if (const auto ph = root["physics"]) {
        s.physics.emplace();
        detail::apply_data_sheet(s.scanner.settings().data_sheet(), *s.physics);  // presets
        detail::parse_physics_block(c, ph, *s.physics);
    }
    if (const auto w = root["weather"]) {
        // The weather acts through the pulse's physics: its defaults when there is no block.
        if (!s.physics) {
            s.physics.emplace();
        }
        s.physics->weather.emplace();
        detail::parse_weather_block(c, w, *s.physics->weather);
    }
    resolve_point_format(c, root, s);
    if (s.point_source_id == PointSourceId::leg && s.leg_scanners.empty()) {
        c.error(root["output"]["point_source_id"], "output.point_source_id",
                "leg needs platform.legs (a platform of type legs with a list of legs)");
    }
    check_laz(c, root, s);
    c.throw_if_any("survey file");
    return s;
}

SurveySpec load_survey_spec(const std::filesystem::path& path) {
    return parse_survey_spec(detail::read_config_text(path, "survey file"), path);
}

}  // namespace beamtrace
