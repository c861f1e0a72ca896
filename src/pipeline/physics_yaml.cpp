#include "pipeline/detail/physics_yaml.hpp"

#include <functional>
#include <numbers>
#include <string>
#include <utility>

#include "beamtrace/sensor/mechanism_presets.hpp"
#include "text/quote.hpp"

namespace beamtrace::detail {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// Reads `n[key]` into `out` (times `scale`) when present.
void number(YamlChecker& c, const YAML::Node& n, const std::string& prefix, const char* key,
            double& out, double scale = 1.0) {
    double v = 0;
    if (n[key] && c.number(n[key], prefix + key, v)) {
        out = v * scale;
    }
}

void flag(YamlChecker& c, const YAML::Node& n, const std::string& prefix, const char* key,
          bool& out) {
    if (const auto f = n[key]) {
        c.boolean(f, prefix + key, out);
    }
}

/// Parses `n[key]` with `parse` (which throws ConfigError for unknown names).
template <typename T, typename Parse>
void choice(YamlChecker& c, const YAML::Node& n, const std::string& prefix, const char* key, T& out,
            Parse parse) {
    if (const auto f = n[key]) {
        try {
            // A name longer than the quote limit matches none: the error quotes it clipped.
            out = parse(f.IsScalar() ? clip_value(f.Scalar()) : std::string());
        } catch (const ConfigError& e) {
            c.error(f, prefix + key, e.what());
        }
    }
}

/// The sub-map `n[key]`, or an undefined node (with an error) when it is not a map.
YAML::Node section(YamlChecker& c, const YAML::Node& n, const char* key) {
    const YAML::Node s = n[key];
    if (s && !s.IsMap()) {
        c.error(s, std::string("physics.") + key, "expected a map");
        return YAML::Node(YAML::NodeType::Undefined);
    }
    return s;
}

/// The georeferencing keys of the `noise:` section (physics/georeferencing.hpp): the random
/// pose errors, their correlation time and the fixed lever-arm and boresight errors.
void parse_georeferencing(YamlChecker& c, const YAML::Node& z, const std::string& q,
                          GeoreferencingConfig& g) {
    number(c, z, q, "position_sigma_m", g.position_sigma_m);
    number(c, z, q, "attitude_sigma_deg", g.attitude_sigma_rad, kDeg);
    number(c, z, q, "correlation_time_s", g.correlation_time_s);
    if (z["lever_arm_error_m"]) {
        c.vec3(z["lever_arm_error_m"], q + "lever_arm_error_m", g.lever_arm_error_m);
    }
    Vec3d bore;
    if (z["boresight_error_deg"] &&
        c.vec3(z["boresight_error_deg"], q + "boresight_error_deg", bore)) {
        g.boresight_error = {bore.x * kDeg, bore.y * kDeg, bore.z * kDeg};
    }
}

/// The `noise:` section.
void parse_noise(YamlChecker& c, const YAML::Node& z, NoiseConfig& k) {
    c.only_keys(z, "physics.noise",
                {"range_sigma_m", "range_sigma_per_m", "angle_jitter_mrad", "position_sigma_m",
                 "attitude_sigma_deg", "correlation_time_s", "lever_arm_error_m",
                 "boresight_error_deg", "dropout_probability"});
    const std::string q = "physics.noise.";
    number(c, z, q, "range_sigma_m", k.range_sigma_m);
    number(c, z, q, "range_sigma_per_m", k.range_sigma_per_m);
    number(c, z, q, "angle_jitter_mrad", k.angle_jitter_rad, 1e-3);
    number(c, z, q, "dropout_probability", k.dropout_probability);
    parse_georeferencing(c, z, q, k.georeferencing);
}

/// The radiometry, the intensity scale (`reference_range_m`: a number or `auto`, the default,
/// which leaves it unset for the survey's pilot) and the BRDF.
void parse_radiometry(YamlChecker& c, const YAML::Node& n, PhysicsConfig& out) {
    const std::string p = "physics.";
    RadiometryConfig& r = out.radiometry;
    number(c, n, p, "wavelength_nm", r.wavelength_nm);
    number(c, n, p, "peak_power_w", r.peak_power_w);
    number(c, n, p, "aperture_diameter_m", r.aperture_diameter_m);
    number(c, n, p, "system_efficiency", r.system_efficiency);
    number(c, n, p, "detection_threshold_w", r.detection_threshold_w);
    choice(c, n, p, "brdf", out.brdf, [](const std::string& s) { return parse_brdf(s); });
    if (const auto i = section(c, n, "intensity")) {
        c.only_keys(i, "physics.intensity", {"reference_range_m", "scale"});
        const YAML::Node range = i["reference_range_m"];
        if (range && !(range.IsScalar() && range.Scalar() == "auto")) {
            double v = 0;
            if (c.number(range, p + "intensity.reference_range_m", v)) {
                r.intensity_reference_range_m = v;
            }
        }
        choice(c, i, p + "intensity.", "scale", r.intensity_scale,
               [](const std::string& s) { return parse_intensity_scale(s); });
    }
}

/// physics.beam: divergence_mrad, rings, exit_diameter_m, edge_samples.
void parse_beam(YamlChecker& c, const YAML::Node& n, PhysicsConfig& out) {
    if (const auto b = section(c, n, "beam")) {
        c.only_keys(b, "physics.beam",
                    {"divergence_mrad", "rings", "exit_diameter_m", "edge_samples"});
        const std::string q = "physics.beam.";
        number(c, b, q, "divergence_mrad", out.beam.divergence_rad, 1e-3);
        long rings = 0;
        if (b["rings"] && c.integer(b["rings"], q + "rings", 0, 20, rings)) {
            out.beam.rings = static_cast<int>(rings);
        }
        number(c, b, q, "exit_diameter_m", out.beam.exit_diameter_m);
        long edge = 0;
        if (b["edge_samples"] && c.integer(b["edge_samples"], q + "edge_samples", 0, 8, edge)) {
            out.beam.edge_samples = static_cast<int>(edge);
        }
    }
}

/// physics.waveform: pulse_fwhm_ns, bin_ns, min_separation_m, min_dip, keep.
void parse_waveform(YamlChecker& c, const YAML::Node& n, PhysicsConfig& out) {
    if (const auto w = section(c, n, "waveform")) {
        c.only_keys(
            w, "physics.waveform",
            {"pulse_fwhm_ns", "pulse_length_ns", "bin_ns", "min_separation_m", "min_dip", "keep"});
        const std::string q = "physics.waveform.";
        number(c, w, q, "pulse_fwhm_ns", out.waveform.pulse_fwhm_ns);
        number(c, w, q, "bin_ns", out.waveform.bin_ns);
        number(c, w, q, "min_separation_m", out.waveform.min_separation_m);
        number(c, w, q, "min_dip", out.waveform.min_dip);
        flag(c, w, q, "keep", out.keep_waveform);
    }
}

/// Reads the positive number `n` at `key` into `out`; false (after reporting) otherwise.
bool positive_number(YamlChecker& c, const YAML::Node& n, const std::string& key, double& out) {
    if (!c.number(n, key, out)) {
        return false;
    }
    if (!(out > 0)) {
        c.error(n, key, "must be positive");
        return false;
    }
    return true;
}

/// waveform.pulse_length_ns: HELIOS++'s pulse length, as the FWHM of its pulse shape.
void parse_pulse_length(YamlChecker& c, const YAML::Node& n, PhysicsConfig& out) {
    const YAML::Node w = n["waveform"];
    if (!w || !w.IsMap() || !w["pulse_length_ns"]) {
        return;
    }
    const std::string key = "physics.waveform.pulse_length_ns";
    double length = 0;
    if (w["pulse_fwhm_ns"]) {
        c.error(w["pulse_length_ns"], key,
                "give pulse_fwhm_ns or pulse_length_ns (HELIOS++'s pulse length), not both");
    } else if (positive_number(c, w["pulse_length_ns"], key, length)) {
        out.waveform.pulse_fwhm_ns = helios_pulse_fwhm_ns(length);
    }
}

/// pulse_energy_uj: the peak power of a Gaussian pulse of that energy and the pulse's FWHM.
void parse_pulse_energy(YamlChecker& c, const YAML::Node& n, PhysicsConfig& out) {
    const YAML::Node e = n["pulse_energy_uj"];
    double uj = 0;
    if (!e) {
        return;
    }
    if (n["peak_power_w"]) {
        c.error(e, "physics.pulse_energy_uj", "give peak_power_w or pulse_energy_uj, not both");
    } else if (positive_number(c, e, "physics.pulse_energy_uj", uj) &&
               out.waveform.pulse_fwhm_ns > 0) {
        out.radiometry.peak_power_w =
            gaussian_pulse_peak_power_w(uj * 1e-6, out.waveform.pulse_fwhm_ns);
    }
}

/// detection: {range_m, reflectance}: the threshold at which the data sheet's range holds, in
/// the survey's atmosphere.
void parse_detection(YamlChecker& c, const YAML::Node& n, PhysicsConfig& out) {
    const YAML::Node d = section(c, n, "detection");
    if (!d) {
        return;
    }
    c.only_keys(d, "physics.detection", {"range_m", "reflectance"});
    if (n["detection_threshold_w"]) {
        c.error(d, "physics.detection", "give detection_threshold_w or detection, not both");
        return;
    }
    double range = 0, reflectance = 0;
    bool ok = true;
    for (const auto& [key, value] :
         {std::pair{"range_m", &range}, std::pair{"reflectance", &reflectance}}) {
        if (!d[key]) {
            c.error(d, "physics.detection", std::string("missing ") + key);
            ok = false;
        } else {
            ok = positive_number(c, d[key], std::string("physics.detection.") + key, *value) && ok;
        }
    }
    if (ok && reflectance > 1.0) {
        c.error(d["reflectance"], "physics.detection.reflectance", "must be in (0, 1]");
        ok = false;
    }
    if (ok) {
        const double alpha = extinction_per_m(out.atmosphere, out.radiometry.wavelength_nm);
        out.radiometry.detection_threshold_w = threshold_for_detection_range_w(
            out.radiometry, range, reflectance, two_way_transmission(alpha, range));
    }
}

}  // namespace

void parse_physics_block(YamlChecker& c, const YAML::Node& n, PhysicsConfig& out) {
    if (!n.IsMap()) {
        c.error(n, "physics", "expected a map");
        return;
    }
    c.only_keys(n, "physics",
                {"wavelength_nm", "peak_power_w", "aperture_diameter_m", "system_efficiency",
                 "detection_threshold_w", "intensity", "brdf", "atmosphere", "beam", "noise",
                 "waveform", "returns", "pulse_energy_uj", "detection"});
    const std::string p = "physics.";
    parse_radiometry(c, n, out);
    if (const auto a = section(c, n, "atmosphere")) {
        c.only_keys(a, "physics.atmosphere",
                    {"enabled", "visibility_km", "model", "extinction_per_m"});
        const std::string q = p + "atmosphere.";
        flag(c, a, q, "enabled", out.atmosphere.enabled);
        number(c, a, q, "visibility_km", out.atmosphere.visibility_km);
        choice(c, a, q, "model", out.atmosphere.model,
               [](const std::string& s) { return parse_extinction_model(s); });
        number(c, a, q, "extinction_per_m", out.atmosphere.extinction_per_m_override);
        if (a["extinction_per_m"] && out.atmosphere.extinction_per_m_override < 0) {
            c.error(a["extinction_per_m"], q + "extinction_per_m", "must not be negative");
        }
    }
    parse_beam(c, n, out);
    if (const auto z = section(c, n, "noise")) {
        parse_noise(c, z, out.noise);
    }
    parse_waveform(c, n, out);
    parse_pulse_length(c, n, out);  // data-sheet units, once the block's other keys are read
    parse_pulse_energy(c, n, out);
    parse_detection(c, n, out);
    if (const auto t = section(c, n, "returns")) {
        c.only_keys(t, "physics.returns", {"mode", "max"});
        choice(c, t, p + "returns.", "mode", out.return_mode,
               [](const std::string& s) { return parse_return_mode(s); });
        long m = 0;
        if (t["max"] && c.integer(t["max"], p + "returns.max", 1, 15, m)) {
            out.max_returns = static_cast<int>(m);
        }
    }
    for (const auto& problem : out.validate()) {
        c.error(n, "physics", problem);
    }
}

void apply_data_sheet(const SensorDataSheet* sheet, PhysicsConfig& out) {
    if (sheet == nullptr) {
        return;
    }
    if (sheet->divergence_mrad > 0.0) {
        out.beam.divergence_rad = sheet->divergence_mrad * 1e-3;
    }
    if (sheet->wavelength_nm > 0.0) {
        out.radiometry.wavelength_nm = sheet->wavelength_nm;
    }
}

}  // namespace beamtrace::detail
