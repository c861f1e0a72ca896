#include "pipeline/detail/survey_physics.hpp"

#include <algorithm>

namespace beamtrace::detail {

SurveyPhysics::SurveyPhysics(const PulseSimulator& sim, const Scene& scene,
                             std::vector<Material> materials, std::uint64_t seed)
    : sim_(&sim), scene_(&scene), materials_(std::move(materials)), seed_(seed) {}

void SurveyPhysics::run(BlockWork& w) const {
    const Scene& scene = *scene_;
    const std::size_t sub_rays = this->sub_rays();
    const std::size_t max_returns = this->max_returns();
    for (std::size_t k = 0; k < w.pulse_count; ++k) {
        for (std::size_t j = 0; j < sub_rays; ++j) {
            const std::size_t h = k * sub_rays + j;
            if (!w.hits.hit(h)) {
                w.sub[j] = SubRayHit{};
                continue;
            }
            const Vec3d d{w.rays.dx[h], w.rays.dy[h], w.rays.dz[h]};
            const double t = w.hits.t[h];
            const ScenePart& part = scene.parts[scene.part_of_face(w.hits.face[h])];
            // The true ray's origin: w.origin is the measured one (georeferencing errors).
            const Vec3d at = Vec3d{w.rays.ox[h], w.rays.oy[h], w.rays.oz[h]} + d * t;
            w.sub[j] = make_sub_ray_hit(materials_[part.material],
                                        scene.pattern_frame(part, w.hits.face[h]), t, at,
                                        scene.geometry.normal_at(w.hits.face[h], at), d);
        }
        sim_->simulate(seed_, w.first + k, w.sub, w.response);
        if (keeps_waveforms()) {
            keep_waveform(w, k);
        }
        const std::size_t n = std::min(w.response.returns.size(), max_returns);
        std::copy_n(w.response.returns.begin(), n,
                    w.returns.begin() + static_cast<std::ptrdiff_t>(k * max_returns));
        w.return_count[k] = static_cast<std::uint8_t>(n);
    }
}

void SurveyPhysics::keep_waveform(BlockWork& w, std::size_t k) const {
    // index, time, beam origin (world), beam axis, first bin, count, samples (float32)
    const auto& samples = w.response.waveform.samples_w;
    PointBlock& block = w.points;
    block.waveforms.push_back({w.first + k, w.pulses.time_s[k], w.origin[k] + scene_->origin_m,
                               w.axis[k], w.response.waveform.first_bin, block.samples.size(),
                               static_cast<std::uint32_t>(samples.size())});
    for (const double s : samples) {
        block.samples.push_back(static_cast<float>(s));
    }
}

}  // namespace beamtrace::detail
