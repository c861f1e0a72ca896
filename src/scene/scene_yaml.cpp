// Scene files in YAML: every problem is collected (file, line, key) and reported at once.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <set>
#include <sstream>

#include "beamtrace/core/error.hpp"
#include "beamtrace/physics/material_library.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "text/quote.hpp"
#include "text/yaml_checker.hpp"

namespace beamtrace {
namespace {

using Checker = detail::YamlChecker;

/// The most copies one part's `array` may make (docs/scene-file.md): each copy stores a
/// transform and, for a sphere, its own primitive, so 10^6 copies take ~100 MB.
constexpr long kMaxArrayCopies = 1000000;

void parse_transform(Checker& c, const YAML::Node& n, const std::string& key, PartTransform& t) {
    if (!n.IsMap()) {
        c.error(n, key, "expected a map with translate_m, rotate_deg, scale");
        return;
    }
    c.only_keys(n, key, {"translate_m", "rotate_deg", "scale"});
    if (n["translate_m"]) {
        c.vec3(n["translate_m"], key + ".translate_m", t.translate_m);
    }
    if (n["rotate_deg"]) {
        Vec3d r;
        if (c.vec3(n["rotate_deg"], key + ".rotate_deg", r)) {
            const double k = std::numbers::pi / 180.0;
            t.rotate = {r.x * k, r.y * k, r.z * k};
        }
    }
    if (const auto s = n["scale"]) {
        double uniform = 1;
        if (s.IsScalar() && c.number(s, key + ".scale", uniform)) {
            t.scale = {uniform, uniform, uniform};
        } else if (!s.IsScalar()) {
            c.vec3(s, key + ".scale", t.scale);
        }
        if (!(t.scale.x > 0 && t.scale.y > 0 && t.scale.z > 0)) {
            c.error(s, key + ".scale", "scale factors must be positive");
        }
    }
}

void parse_array(Checker& c, const YAML::Node& n, const std::string& key, PartArray& a) {
    if (!n.IsMap()) {
        c.error(n, key, "expected a map with count and step_m");
        return;
    }
    c.only_keys(n, key, {"count", "step_m"});
    if (const auto cn = n["count"]) {
        if (!cn.IsSequence() || cn.size() != 3) {
            c.error(cn, key + ".count", "expected [nx, ny, nz]");
        } else {
            bool ok = true;
            for (std::size_t i = 0; i < 3; ++i) {
                ok = c.integer(cn[i], key + ".count", 1, kMaxArrayCopies, a.count[i]) && ok;
            }
            if (ok && a.copies() > static_cast<std::uint64_t>(kMaxArrayCopies)) {
                c.error(cn, key + ".count",
                        std::to_string(a.copies()) + " copies, more than the limit of " +
                            std::to_string(kMaxArrayCopies) + " copies of a part");
            }
        }
    } else {
        c.error(n, key + ".count", "missing");
    }
    if (n["step_m"]) {
        c.vec3(n["step_m"], key + ".step_m", a.step_m);
    }
}

/// One key of `motion.keyframes`: {time_s, position_m, rotate_deg}.
void parse_key(Checker& c, const YAML::Node& n, const std::string& key, MotionKey& k) {
    if (!n.IsMap()) {
        c.error(n, key, "expected a map with time_s, position_m, rotate_deg");
        return;
    }
    c.only_keys(n, key, {"time_s", "position_m", "rotate_deg"});
    if (!n["time_s"]) {
        c.error(n, key + ".time_s", "missing");
    } else {
        c.number(n["time_s"], key + ".time_s", k.time_s);
    }
    if (n["position_m"]) {
        c.vec3(n["position_m"], key + ".position_m", k.position_m);
    }
    Vec3d r{0, 0, 0};
    if (n["rotate_deg"] && c.vec3(n["rotate_deg"], key + ".rotate_deg", r)) {
        const double d = std::numbers::pi / 180.0;
        k.attitude = Quat::from_rpy({r.x * d, r.y * d, r.z * d});
    }
}

void parse_keyframes(Checker& c, const YAML::Node& n, const std::string& key, PartMotion& m) {
    if (!n.IsSequence() || n.size() == 0 || n.size() > 100000) {
        c.error(n, key, "expected a list of 1 to 100000 keys {time_s, position_m, rotate_deg}");
        return;
    }
    for (std::size_t i = 0; i < n.size(); ++i) {
        MotionKey k;
        parse_key(c, n[i], key + "[" + std::to_string(i) + "]", k);
        if (!m.keys.empty() && !(k.time_s > m.keys.back().time_s)) {
            c.error(n[i], key + "[" + std::to_string(i) + "].time_s",
                    "keys must be in strictly increasing time (" + std::to_string(k.time_s) +
                        " s after " + std::to_string(m.keys.back().time_s) + " s)");
        }
        m.keys.push_back(k);
    }
}

void parse_spin(Checker& c, const YAML::Node& n, const std::string& key, PartMotion& m) {
    if (!n.IsMap()) {
        c.error(n, key, "expected a map with axis, rate_rad_s, pivot_m");
        return;
    }
    c.only_keys(n, key, {"axis", "rate_rad_s", "pivot_m"});
    if (n["axis"] && c.vec3(n["axis"], key + ".axis", m.spin_axis)) {
        if (length(m.spin_axis) == 0.0) {
            c.error(n["axis"], key + ".axis", "must not be zero");
        } else {
            m.spin_axis = normalize(m.spin_axis);
        }
    }
    if (!n["rate_rad_s"]) {
        c.error(n, key + ".rate_rad_s", "missing");
    } else {
        c.number(n["rate_rad_s"], key + ".rate_rad_s", m.spin_rate_rad_s);
    }
    if (n["pivot_m"]) {
        Vec3d pivot;
        if (c.vec3(n["pivot_m"], key + ".pivot_m", pivot)) {
            m.pivot_m = pivot;
        }
    }
}

/// `motion: {keyframes: [...]}` or `motion: {velocity_mps: [...], spin: {...}}`.
void parse_motion(Checker& c, const YAML::Node& n, const std::string& key, PartMotion& m) {
    if (!n.IsMap()) {
        c.error(n, key, "expected a map with keyframes, or velocity_mps and/or spin");
        return;
    }
    c.only_keys(n, key, {"keyframes", "velocity_mps", "spin"});
    if (const auto k = n["keyframes"]) {
        parse_keyframes(c, k, key + ".keyframes", m);
        for (const char* other : {"velocity_mps", "spin"}) {
            if (n[other]) {
                c.error(n[other], key + "." + other,
                        "not with keyframes (a part moves by keyframes or by a constant velocity "
                        "and spin)");
            }
        }
        return;
    }
    if (!n["velocity_mps"] && !n["spin"]) {
        c.error(n, key, "expected keyframes, or velocity_mps and/or spin");
    }
    if (n["velocity_mps"]) {
        c.vec3(n["velocity_mps"], key + ".velocity_mps", m.velocity_mps);
    }
    if (const auto s = n["spin"]) {
        parse_spin(c, s, key + ".spin", m);
    }
}

/// The copies of all parts together stay within kMaxArrayCopies (each part's own count is
/// checked by parse_array).
void check_total_copies(Checker& c, const YAML::Node& parts, const SceneSpec& spec) {
    std::uint64_t total = 0;
    for (const PartSpec& p : spec.parts) {
        if (p.array.copies() > static_cast<std::uint64_t>(kMaxArrayCopies)) {
            return;  // reported for the part
        }
        total += p.array.copies();
    }
    if (total > static_cast<std::uint64_t>(kMaxArrayCopies)) {
        c.error(parts, "parts",
                std::to_string(total) + " copies of parts in all, more than the limit of " +
                    std::to_string(kMaxArrayCopies) + " copies in a scene");
    }
}

void parse_part(Checker& c, const YAML::Node& n, std::size_t index, SceneSpec& spec) {
    const std::string key = "parts[" + std::to_string(index) + "]";
    if (!n.IsMap()) {
        c.error(n, key, "expected a map");
        return;
    }
    c.only_keys(n, key,
                {"name", "mesh", "raster", "sphere", "plane", "transform", "array", "material",
                 "label", "part_id", "up_axis", "motion"});
    PartSpec p;
    p.part_id = static_cast<std::uint16_t>(std::min<std::size_t>(index + 1, 65535));
    int kinds = 0;
    const auto dir = spec.source.parent_path();
    for (const char* k : {"mesh", "raster"}) {
        if (const auto f = n[k]) {
            ++kinds;
            p.kind = std::string(k) == "mesh" ? PartKind::mesh : PartKind::raster;
            if (!f.IsScalar() || f.Scalar().empty()) {
                c.error(f, key + "." + k, "expected a file name");
            } else {
                p.file = dir / f.Scalar();
                c.existing_file(f, key + "." + k, p.file);
            }
        }
    }
    if (const auto s = n["sphere"]) {
        ++kinds;
        p.kind = PartKind::sphere;
        const std::string sk = key + ".sphere";
        if (!s.IsMap()) {
            c.error(s, sk, "expected a map with center_m, radius_m");
        } else {
            c.only_keys(s, sk, {"center_m", "radius_m", "subdivisions", "exact"});
            if (s["center_m"]) {
                c.vec3(s["center_m"], sk + ".center_m", p.center_m);
            }
            if (s["radius_m"] && c.number(s["radius_m"], sk + ".radius_m", p.radius_m) &&
                !(p.radius_m > 0)) {
                c.error(s["radius_m"], sk + ".radius_m", "must be positive");
            }
            long sub = p.sphere_subdivisions;
            if (s["subdivisions"] &&
                c.integer(s["subdivisions"], sk + ".subdivisions", 0, 8, sub)) {
                p.sphere_subdivisions = static_cast<int>(sub);
            }
            if (s["exact"] && c.boolean(s["exact"], sk + ".exact", p.exact_sphere) &&
                p.exact_sphere && s["subdivisions"]) {
                c.error(s["subdivisions"], sk + ".subdivisions",
                        "an exact sphere has no subdivisions (drop one of exact, subdivisions)");
            }
        }
    }
    if (const auto s = n["plane"]) {
        ++kinds;
        p.kind = PartKind::plane;
        const std::string pk = key + ".plane";
        if (!s.IsMap()) {
            c.error(s, pk, "expected a map with point_m, normal, size_m");
        } else {
            c.only_keys(s, pk, {"point_m", "normal", "size_m"});
            if (s["point_m"]) {
                c.vec3(s["point_m"], pk + ".point_m", p.point_m);
            }
            if (s["normal"] && c.vec3(s["normal"], pk + ".normal", p.normal) &&
                length(p.normal) == 0.0) {
                c.error(s["normal"], pk + ".normal", "must not be zero");
            }
            if (s["size_m"] && c.number(s["size_m"], pk + ".size_m", p.size_m) && !(p.size_m > 0)) {
                c.error(s["size_m"], pk + ".size_m", "must be positive");
            }
        }
    }
    if (kinds != 1) {
        c.error(n, key, "needs exactly one of mesh, raster, sphere, plane");
    }
    if (const auto nm = n["name"]) {
        p.name = nm.IsScalar() ? nm.Scalar() : "";
        if (p.name.empty()) {
            c.error(nm, key + ".name", "expected a non-empty string");
        }
    } else {
        p.name = !p.file.empty() ? p.file.filename().string() : "part-" + std::to_string(index + 1);
    }
    if (const auto t = n["transform"]) {
        parse_transform(c, t, key + ".transform", p.transform);
    }
    if (const auto a = n["array"]) {
        parse_array(c, a, key + ".array", p.array);
    }
    if (const auto u = n["up_axis"]) {
        if (p.kind != PartKind::mesh) {
            c.error(u, key + ".up_axis", "only a mesh part has an up axis of its own");
        } else if (!u.IsScalar() || (u.Scalar() != "y" && u.Scalar() != "z")) {
            c.error(u, key + ".up_axis", "expected y (the mesh's +y is up) or z (the default)");
        } else {
            p.transform.y_up = u.Scalar() == "y";
        }
    }
    if (p.exact_sphere) {
        const Vec3d& k = p.transform.scale;
        if (!(k.x == k.y && k.y == k.z)) {
            c.error(n["transform"], key + ".transform.scale",
                    "an exact sphere needs the same scale on every axis (it would be an "
                    "ellipsoid); use subdivisions instead of exact");
        }
    }
    if (const auto mo = n["motion"]) {
        parse_motion(c, mo, key + ".motion", p.motion.emplace());
        if (p.exact_sphere) {
            c.error(mo, key + ".motion",
                    "an exact sphere cannot move (drop exact to move the sphere as triangles)");
        }
    }
    if (const auto m = n["material"]) {
        p.material = m.IsScalar() ? m.Scalar() : "";
        if (spec.find_material(p.material) == nullptr) {
            c.error(m, key + ".material", "unknown material " + detail::quote_value(p.material));
        }
    }
    long v = 0;
    if (n["label"] && c.integer(n["label"], key + ".label", 0, 255, v)) {
        p.label = static_cast<std::uint8_t>(v);
    }
    if (n["part_id"] && c.integer(n["part_id"], key + ".part_id", 0, 65535, v)) {
        p.part_id = static_cast<std::uint16_t>(v);
    }
    spec.parts.push_back(std::move(p));
}

/// `color: [r, g, b]`, each in [0, 1].
void parse_color(Checker& c, const YAML::Node& n, const std::string& key, Vec3d& color) {
    if (c.vec3(n, key, color) && !(color.x >= 0.0 && color.x <= 1.0 && color.y >= 0.0 &&
                                   color.y <= 1.0 && color.z >= 0.0 && color.z <= 1.0)) {
        c.error(n, key, "every channel must be in [0, 1]");
    }
}

/// `pattern: {kind: stripes|checker|none, count: 8, size_m: 1, reflectance: 0.1, colors: [...]}`.
void parse_pattern(Checker& c, const YAML::Node& n, const std::string& key, AlbedoPattern& p) {
    if (!n.IsMap()) {
        c.error(n, key, "expected a map with kind, count, size_m, reflectance");
        return;
    }
    c.only_keys(n, key, {"kind", "count", "size_m", "reflectance", "colors"});
    const auto kind = n["kind"];
    if (!kind || !kind.IsScalar() ||
        (kind.Scalar() != "stripes" && kind.Scalar() != "checker" && kind.Scalar() != "none")) {
        c.error(kind ? kind : n, key + ".kind", "expected stripes, checker or none");
    } else {
        p.kind = kind.Scalar() == "stripes"   ? AlbedoPatternKind::stripes
                 : kind.Scalar() == "checker" ? AlbedoPatternKind::checker
                                              : AlbedoPatternKind::uniform;
    }
    long count = p.count;
    if (n["count"] && c.integer(n["count"], key + ".count", 2, 1000, count)) {
        p.count = static_cast<int>(count);
    }
    if (n["size_m"] && c.number(n["size_m"], key + ".size_m", p.size_m) && !(p.size_m > 0)) {
        c.error(n["size_m"], key + ".size_m", "must be positive");
    }
    double& r = p.alternate_reflectance;
    if (n["reflectance"] && c.number(n["reflectance"], key + ".reflectance", r) &&
        !(r >= 0.0 && r <= 1.0)) {
        c.error(n["reflectance"], key + ".reflectance", "must be in [0, 1]");
    }
    if (const auto cs = n["colors"]) {
        if (!cs.IsSequence() || cs.size() == 0 || cs.size() > 1000) {
            c.error(cs, key + ".colors", "expected a list of 1 to 1000 colours [r, g, b]");
            return;
        }
        for (std::size_t i = 0; i < cs.size(); ++i) {
            Vec3d colour{1, 1, 1};
            parse_color(c, cs[i], key + ".colors[" + std::to_string(i) + "]", colour);
            p.colors.push_back(colour);
        }
    }
}

void parse_material(Checker& c, const YAML::Node& n, std::size_t index, SceneSpec& spec,
                    std::set<std::string>& names) {
    const std::string key = "materials[" + std::to_string(index) + "]";
    if (!n.IsMap()) {
        c.error(n, key, "expected a map");
        return;
    }
    c.only_keys(n, key,
                {"name", "reflectance", "specular_weight", "specular_exponent", "pattern",
                 "library", "color"});
    Material m;
    if (!n["name"] || !n["name"].IsScalar() || n["name"].Scalar().empty()) {
        c.error(n, key + ".name", "every material needs a name");
    } else {
        m.name = n["name"].Scalar();
        if (!names.insert(m.name).second) {
            c.error(n["name"], key + ".name", "duplicate material " + detail::quote_value(m.name));
        }
    }
    const auto unit = [&](const char* k, double& out) {
        if (n[k] && c.number(n[k], key + "." + k, out) && !(out >= 0.0 && out <= 1.0)) {
            c.error(n[k], key + "." + k, "must be in [0, 1]");
        }
    };
    unit("reflectance", m.reflectance);
    unit("specular_weight", m.specular_weight);
    if (n["specular_exponent"] &&
        c.number(n["specular_exponent"], key + ".specular_exponent", m.specular_exponent) &&
        !(m.specular_exponent > 0)) {
        c.error(n["specular_exponent"], key + ".specular_exponent", "must be positive");
    }
    if (const auto pn = n["pattern"]) {
        parse_pattern(c, pn, key + ".pattern", m.pattern);
    }
    if (const auto cn = n["color"]) {
        parse_color(c, cn, key + ".color", m.color);
    }
    if (const auto lib = n["library"]) {
        if (!lib.IsScalar() || lib.Scalar().empty()) {
            c.error(lib, key + ".library", "expected a material name (docs/physics.md)");
        } else if (!library_material(lib.Scalar(), 905.0)) {
            c.error(lib, key + ".library",
                    "unknown library material " + detail::quote_value(lib.Scalar()) +
                        " (known: " + material_library_names() + ")");
        } else {
            m.library = lib.Scalar();
        }
        for (const char* k : {"reflectance", "specular_weight", "specular_exponent"}) {
            if (n[k]) {
                c.error(n[k], key + "." + k, "not with 'library', which sets it");
            }
        }
    }
    spec.materials.push_back(m);
}

/// `crs: EPSG:<code>` or `crs: <OGC WKT>` (core/crs.hpp).
void parse_crs(Checker& c, const YAML::Node& n, SceneSpec& spec) {
    if (!n.IsScalar()) {
        c.error(n, "crs", "expected EPSG:<code> or an OGC WKT string");
        return;
    }
    std::string problem;
    if (auto crs = parse_crs_text(n.Scalar(), problem)) {
        spec.crs = std::move(*crs);
    } else {
        c.error(n, "crs", problem);
    }
}

}  // namespace

Affine3 PartTransform::to_affine() const {
    const Mat3 r = Quat::from_rpy(rotate).to_matrix();
    Affine3 a;
    for (int i = 0; i < 3; ++i) {
        a.linear.m[i][0] = r.m[i][0] * scale.x;
        a.linear.m[i][1] = r.m[i][1] * scale.y;
        a.linear.m[i][2] = r.m[i][2] * scale.z;
        if (y_up) {  // first (x, y, z) -> (x, -z, y): columns 1, 2 become 2, -1
            const double c1 = a.linear.m[i][1];
            a.linear.m[i][1] = a.linear.m[i][2];
            a.linear.m[i][2] = -c1;
        }
    }
    a.translation = translate_m;
    return a;
}

const Material* SceneSpec::find_material(const std::string& name) const {
    for (const auto& m : materials) {
        if (m.name == name) {
            return &m;
        }
    }
    return nullptr;
}

SceneSpec parse_scene_spec(const std::string& yaml_text, const std::filesystem::path& source) {
    const YAML::Node root = detail::parse_yaml(yaml_text, source);
    Checker c(source);
    SceneSpec spec;
    spec.source = source;
    spec.materials.emplace_back().name = "default";
    if (!root.IsMap()) {
        throw ConfigError(source.string() + ": expected a map with 'parts' at the top level");
    }
    c.only_keys(root, "", {"origin_m", "crs", "materials", "parts"});
    if (root["origin_m"]) {
        c.vec3(root["origin_m"], "origin_m", spec.origin_m);
    }
    if (const auto crs = root["crs"]) {
        parse_crs(c, crs, spec);
    }
    std::set<std::string> names{"default"};
    if (const auto ms = root["materials"]) {
        if (!ms.IsSequence()) {
            c.error(ms, "materials", "expected a list");
        } else {
            for (std::size_t i = 0; i < ms.size(); ++i) {
                parse_material(c, ms[i], i, spec, names);
            }
        }
    }
    const auto ps = root["parts"];
    if (!ps || !ps.IsSequence() || ps.size() == 0) {
        c.error(ps ? ps : root, "parts", "expected a non-empty list of parts");
    } else {
        for (std::size_t i = 0; i < ps.size(); ++i) {
            parse_part(c, ps[i], i, spec);
        }
        check_total_copies(c, ps, spec);
    }
    c.throw_if_any("scene file");
    return spec;
}

SceneSpec load_scene_spec(const std::filesystem::path& path) {
    return parse_scene_spec(detail::read_config_text(path, "scene file"), path);
}

}  // namespace beamtrace
