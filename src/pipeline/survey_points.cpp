#include "pipeline/detail/survey_points.hpp"

namespace beamtrace::detail {

void SurveyPoints::run(BlockWork& w) const {
    std::vector<BlockPoint>& out = w.points.points;
    out.reserve(w.pulse_count * max_returns);
    for (std::size_t k = 0; k < w.pulse_count; ++k) {
        const std::size_t n = physics ? w.return_count[k] : (w.hits.hit(k) ? 1 : 0);
        for (std::size_t r = 0; r < n; ++r) {
            const PulseReturn* ret = physics ? &w.returns[k * max_returns + r] : nullptr;
            const std::size_t h = physics ? k * sub_rays + ret->sub_ray : k;
            const double t = physics ? ret->range_m : double{w.hits.t[k]};
            const ScenePart& part = scene->parts[scene->part_of_face(w.hits.face[h])];
            const Vec3d xyz = w.origin[k] + w.axis[k] * t + scene->origin_m;
            BlockPoint& p = out.emplace_back();
            p.x = xyz.x;
            p.y = xyz.y;
            p.z = xyz.z;
            p.gps_time = w.pulses.time_s[k];
            p.range_m = static_cast<float>(t);
            p.scan_angle_deg = w.scan_angle[k];
            p.face = w.hits.face[h];
            p.return_number = ret ? ret->return_number : 1;
            p.number_of_returns = ret ? ret->number_of_returns : 1;
            p.intensity = ret ? ret->intensity : 0;
            p.classification = part.label;
            p.point_source_id = part.part_id;
            p.channel = w.pulses.channel[k];
            p.user_data = static_cast<std::uint8_t>(w.pulses.channel[k] & 0xFFu);  // beam / row
            p.pulse = w.first + k;
        }
    }
}

}  // namespace beamtrace::detail
