#include "pipeline/detail/survey_points.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "beamtrace/sensor/leg_sequence.hpp"

namespace beamtrace::detail {

namespace {

/// A linear channel in [0, 1] as a 16-bit sRGB value.
std::uint16_t srgb16(double linear) {
    const double c = std::clamp(linear, 0.0, 1.0);
    const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
    return static_cast<std::uint16_t>(std::lround(s * 65535.0));
}

}  // namespace

std::vector<std::array<std::uint16_t, 4>> part_colours(const Scene& scene,
                                                       const std::vector<Material>& materials) {
    std::vector<std::array<std::uint16_t, 4>> out;
    for (const ScenePart& part : scene.parts) {
        const Material& m = part.material < materials.size() ? materials[part.material]
                                                             : scene.materials.at(part.material);
        out.push_back({srgb16(m.color.x), srgb16(m.color.y), srgb16(m.color.z),
                       static_cast<std::uint16_t>(
                           std::lround(std::clamp(m.reflectance, 0.0, 1.0) * 65535.0))});
    }
    return out;
}

float SurveyPoints::incidence_deg(const BlockWork& w, std::size_t k, std::size_t r) const {
    double c = 1.0;
    if (physics) {
        c = w.return_cos_incidence[k * max_returns + r];
    } else {
        const std::size_t h = k * sub_rays;  // the pulse's central ray
        const Vec3d d{w.rays.dx[h], w.rays.dy[h], w.rays.dz[h]};
        const Vec3d at = Vec3d{w.rays.ox[h], w.rays.oy[h], w.rays.oz[h]} + d * double{w.hits.t[h]};
        const Vec3d n = scene->normal_at(w.hits.face[h], at, w.pulses.time_s[k]);
        const double nd = length(n) * length(d);
        c = nd > 0 ? std::abs(dot(n, d)) / nd : 0.0;
    }
    return static_cast<float>(std::acos(std::clamp(c, 0.0, 1.0)) * 180.0 / std::numbers::pi);
}

void SurveyPoints::medium_point(BlockPoint& p, const PulseReturn& ret) const {
    p.face = kNoFace;
    p.classification = medium_class;
    p.point_source_id = 0;
    p.weather = static_cast<std::uint8_t>(ret.weather);
    p.incidence_deg = 0.0f;
}

void SurveyPoints::set_sources(const SurveySpec& spec, const ScanPattern& pattern) {
    for (const SurveyScanner& s : spec.scanners) {
        scanner_channels.push_back(s.channel);
    }
    by_scanner = spec.point_source_id == PointSourceId::scanner;
    if (spec.point_source_id != PointSourceId::leg) {
        return;
    }
    if (const auto* legs = dynamic_cast<const LegSequence*>(&pattern)) {
        leg_first_pulse = legs->first_pulses();
    } else if (!spec.scanners.empty() && !spec.leg_scanners.empty()) {
        leg_start_s = LinearLegs(spec.legs).waypoint_times_s();
        leg_start_s.pop_back();  // the last waypoint ends the last leg
    }
}

std::uint16_t SurveyPoints::pulse_source_id(const BlockWork& w, std::size_t k) const {
    if (by_scanner) {
        return w.pulses.scanner[k];
    }
    if (!leg_first_pulse.empty()) {
        return static_cast<std::uint16_t>(leg_of_pulse(leg_first_pulse, w.first + k));
    }
    if (!leg_start_s.empty()) {
        const auto it =
            std::upper_bound(leg_start_s.begin(), leg_start_s.end(), w.pulses.time_s[k]);
        return static_cast<std::uint16_t>(std::max<std::ptrdiff_t>(it - leg_start_s.begin(), 1) -
                                          1);
    }
    return 0;
}

[[gnu::always_inline]] inline void SurveyPoints::part_fields(BlockPoint& p, const BlockWork& w,
                                                             std::size_t k, std::size_t r,
                                                             std::uint32_t face, const Vec3d& xyz,
                                                             bool by_pulse,
                                                             std::size_t& last_part) const {
    // Neighbouring points mostly hit the same part: try the last one before searching.
    if (const ScenePart& cached = scene->parts[last_part];
        face - cached.first_face >= cached.face_count) {
        last_part = scene->part_of_face(face);
    }
    const ScenePart& part = scene->parts[last_part];
    p.face = face;
    p.classification = part.label;
    if (!by_pulse) {
        p.point_source_id = part.part_id;
    }
    if (incidence) {
        p.incidence_deg = incidence_deg(w, k, r);
    }
    if (instance) {
        p.instance_id = scene->object_of_face(face);
    }
    if (velocity) {
        p.velocity_mps = Vec3f(scene->velocity_at(face, xyz - scene->origin_m, p.gps_time));
    }
    if (!colours.empty()) {
        const auto& c = colours[last_part];
        p.red = c[0];
        p.green = c[1];
        p.blue = c[2];
        p.nir = c[3];
    }
}

bool SurveyPoints::hits_alone() const {
    return !physics && !no_echo && !incidence && !instance && !velocity && colours.empty() &&
           leg_first_pulse.empty() && leg_start_s.empty() && !by_scanner &&
           scanner_channels.empty() && !scene->parts.empty();
}

void SurveyPoints::run(BlockWork& w) const {
    if (physics) {
        run_pulses<true>(w);
    } else if (hits_alone()) {
        run_hits(w);
    } else {
        run_pulses<false>(w);
    }
}

namespace {

/// What run_pulses() reads of a block for every point, as local pointers and values: read
/// through BlockWork, the scene and the vector of points, each was loaded again after every
/// byte-sized store into a point (a char store may alias anything), a third of the stage's
/// instructions.
struct PulseArrays {
    const Vec3d* origin;  ///< physics: the beams as measured
    const Vec3d* axis;
    const double *ox, *oy, *oz, *dx, *dy, *dz;  ///< without physics: the rays (the beams)
    const double* time_s;
    const float* scan_angle;
    const std::uint16_t* channel;
    const std::uint8_t* scanner;
    const float* hit_t;
    const std::uint32_t* hit_face;
    Vec3d origin_m;
    std::uint64_t first;
};

/// Each point starts as a copy of this one (every field its default), copied from memory: a
/// 112-byte default construction per point compiled to `rep stos`, and a blank of the function's
/// own was rebuilt on the stack by narrow stores and read back as 16-byte pieces for every point
/// (stalled store forwarding, two thirds of the stage's time at 2 threads).
const BlockPoint kBlankPoint{};

/// A hit point's blank: a point's defaults, one return of one.
constexpr BlockPoint kBlankHit = [] {
    BlockPoint p;
    p.return_number = 1;
    p.number_of_returns = 1;
    return p;
}();

/// The fields a point takes from its part, of the part that was hit last (part_fields() without
/// the optional ones), in locals: faces [first_face, first_face + face_count).
struct PartCache {
    std::uint32_t first_face, face_count;
    std::uint8_t label;
    std::uint16_t part_id;

    explicit PartCache(const ScenePart& part)
        : first_face(part.first_face),
          face_count(part.face_count),
          label(part.label),
          part_id(part.part_id) {}
};

}  // namespace

void SurveyPoints::run_hits(BlockWork& w) const {
    const double *ox = w.rays.ox.data(), *oy = w.rays.oy.data(), *oz = w.rays.oz.data();
    const double *dx = w.rays.dx.data(), *dy = w.rays.dy.data(), *dz = w.rays.dz.data();
    const double* time_s = w.pulses.time_s.data();
    const float* scan_angle = w.scan_angle.data();
    const std::uint16_t* channel = w.pulses.channel.data();
    const float* hit_t = w.hits.t.data();
    const std::uint32_t* hit_face = w.hits.face.data();
    const Vec3d origin_m = scene->origin_m;
    const std::uint64_t first = w.first;
    const std::size_t pulse_count = w.pulse_count;
    std::vector<BlockPoint>& out = w.points.points;
    out.reserve(out.size() + pulse_count);
    PartCache part(scene->parts[0]);  // the part of the last hit, as part_fields() tries first
    for (std::size_t k = 0; k < pulse_count; ++k) {
        const std::uint32_t face = hit_face[k];
        if (face == kNoFace) {
            continue;
        }
        const double t = double{hit_t[k]};
        const Vec3d xyz = Vec3d{ox[k], oy[k], oz[k]} + Vec3d{dx[k], dy[k], dz[k]} * t + origin_m;
        if (face - part.first_face >= part.face_count) {
            part = PartCache(scene->parts[scene->part_of_face(face)]);
        }
        BlockPoint* const p = &out.emplace_back(kBlankHit);
        p->x = xyz.x;
        p->y = xyz.y;
        p->z = xyz.z;
        p->gps_time = time_s[k];
        p->range_m = static_cast<float>(t);
        p->scan_angle_deg = scan_angle[k];
        p->channel = channel[k];
        p->user_data = static_cast<std::uint8_t>(channel[k] & 0xFFu);  // beam / row
        p->pulse = first + k;
        p->face = face;
        p->classification = part.label;
        p->point_source_id = part.part_id;
    }
}

template <bool Physics>
void SurveyPoints::run_pulses(BlockWork& w) const {
    const PulseArrays a{w.origin.data(),         w.axis.data(),
                        w.rays.ox.data(),        w.rays.oy.data(),
                        w.rays.oz.data(),        w.rays.dx.data(),
                        w.rays.dy.data(),        w.rays.dz.data(),
                        w.pulses.time_s.data(),  w.scan_angle.data(),
                        w.pulses.channel.data(), w.pulses.scanner.data(),
                        w.hits.t.data(),         w.hits.face.data(),
                        scene->origin_m,         w.first};
    std::vector<BlockPoint>& out = w.points.points;
    out.reserve(out.size() + w.pulse_count * max_returns);
    std::size_t last_part = 0;  // the part of the last hit (see part_fields)
    const bool by_pulse = by_scanner || !leg_first_pulse.empty() || !leg_start_s.empty();
    const bool any_channel = !scanner_channels.empty();
    for (std::size_t k = 0; k < w.pulse_count; ++k) {
        const std::size_t n = Physics ? w.return_count[k] : (a.hit_face[k] != kNoFace ? 1 : 0);
        // Without physics the pulse's beam is its ray (SurveyRaySource::generate).
        const Vec3d origin = Physics ? a.origin[k] : Vec3d{a.ox[k], a.oy[k], a.oz[k]};
        const Vec3d axis = Physics ? a.axis[k] : Vec3d{a.dx[k], a.dy[k], a.dz[k]};
        if (no_echo && n == 0) {
            w.points.no_echo.push_back(
                {a.first + k, a.time_s[k], origin + a.origin_m, axis, a.scanner[k]});
        }
        const std::uint16_t source = by_pulse ? pulse_source_id(w, k) : 0;
        const std::uint8_t scanner_channel = any_channel ? scanner_channels[a.scanner[k]] : 0;
        const double time_s = a.time_s[k];
        const float scan_angle = a.scan_angle[k];
        const std::uint16_t channel = a.channel[k];
        for (std::size_t r = 0; r < n; ++r) {
            const PulseReturn* ret = Physics ? &w.returns[k * max_returns + r] : nullptr;
            const std::uint32_t face = Physics ? w.return_face[k * max_returns + r] : a.hit_face[k];
            const double t = Physics ? ret->range_m : double{a.hit_t[k]};
            const Vec3d xyz = origin + axis * t + a.origin_m;
            BlockPoint* const p = &out.emplace_back(kBlankPoint);
            p->x = xyz.x;
            p->y = xyz.y;
            p->z = xyz.z;
            p->gps_time = time_s;
            p->range_m = static_cast<float>(t);
            p->scan_angle_deg = scan_angle;
            p->return_number = Physics ? ret->return_number : 1;
            p->number_of_returns = Physics ? ret->number_of_returns : 1;
            p->intensity = Physics ? ret->intensity : 0;
            p->channel = channel;
            p->user_data = static_cast<std::uint8_t>(channel & 0xFFu);  // beam / row
            p->pulse = a.first + k;
            p->scanner_channel = scanner_channel;
            p->point_source_id = source;
            if constexpr (Physics) {
                p->echo_width_ns = static_cast<float>(ret->echo_width_ns);
            }
            if (Physics && ret->weather != WeatherEffect::none) {
                medium_point(*p, *ret);
                p->point_source_id = source;
                continue;
            }
            part_fields(*p, w, k, r, face, xyz, by_pulse, last_part);
        }
    }
}

}  // namespace beamtrace::detail
