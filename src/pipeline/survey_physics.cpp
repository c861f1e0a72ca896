#include "pipeline/detail/survey_physics.hpp"

#include <algorithm>
#include <cmath>

namespace beamtrace::detail {
namespace {

/// The pattern frame of a uniform albedo, which does not read it.
const PatternFrame kUnread{};

/// Whether faces[0, n) are all faces[0] (without a branch a face: the loop runs in lanes).
bool one_face(const std::uint32_t* faces, std::size_t n) {
    std::uint32_t differ = 0;
    for (std::size_t j = 1; j < n; ++j) {
        differ |= faces[j] ^ faces[0];
    }
    return differ == 0;
}

}  // namespace

SurveyPhysics::SurveyPhysics(const PulseSimulator& sim, const Scene& scene,
                             std::vector<Material> materials, std::uint64_t seed)
    : sim_(&sim), scene_(&scene), materials_(std::move(materials)), seed_(seed) {}

const SurveyPhysics::FaceFacts& SurveyPhysics::face_facts(std::uint32_t face, const Vec3d& point_m,
                                                          double time_s, FaceCache& cache) const {
    for (const FaceFacts& f : cache.faces) {
        if (f.face == face && (f.still || f.time_s == time_s)) {
            return f;
        }
    }
    FaceFacts& f = cache.faces[cache.next];
    cache.next = (cache.next + 1) % cache.faces.size();
    const Scene& scene = *scene_;
    const ScenePart& part = scene.parts[scene.part_of_face(face)];
    f.face = face;
    f.part = &part;
    f.material = &materials_[part.material];
    // Only a sphere's normal depends on the point (a moving face's on the time: one pulse's).
    f.flat = scene.geometry.sphere_of_face(face) == nullptr;
    f.still = scene.moving_of_face(face) == nullptr;
    f.time_s = time_s;
    if (f.flat) {
        f.normal = scene.normal_at(face, point_m, time_s);
    }
    return f;
}

SubRayHit SurveyPhysics::sub_ray_hit(const RayBatch& rays, const HitBatch& hits, std::size_t h,
                                     double time_s, FaceCache& cache) const {
    if (!hits.hit(h)) {
        return SubRayHit{};
    }
    const std::uint32_t face = hits.face[h];
    const Vec3d d{rays.dx[h], rays.dy[h], rays.dz[h]};
    const double t = hits.t[h];
    // The true ray's origin: w.origin is the measured one (georeferencing errors).
    const Vec3d at = Vec3d{rays.ox[h], rays.oy[h], rays.oz[h]} + d * t;
    const FaceFacts& f = face_facts(face, at, time_s, cache);
    const Vec3d normal = f.flat ? f.normal : scene_->normal_at(face, at, time_s);
    if (f.material->pattern.kind == AlbedoPatternKind::uniform) {
        return make_sub_ray_hit(*f.material, kUnread, t, at, normal, d);
    }
    return make_sub_ray_hit(*f.material, scene_->pattern_frame(*f.part, face), t, at, normal, d);
}

void SurveyPhysics::find_edges(BlockWork& w) const {
    const std::size_t sub_rays = this->sub_rays();
    const std::size_t probes = sim_->probes_per_cell();
    w.edge_cell.clear();
    w.edge_start.assign(w.pulse_count + 1, 0);
    if (probes == 0) {
        return;
    }
    w.target.resize(sub_rays);
    std::uint32_t last_face = kNoFace;  // and its part: neighbouring sub-rays meet the same faces
    std::int64_t last_part = -1;
    for (std::size_t k = 0; k < w.pulse_count; ++k) {
        // Sub-rays that all meet one face (or none) meet one part: no edge (edge_cells).
        if (one_face(w.hits.face.data() + k * sub_rays, sub_rays)) {
            w.edge_start[k + 1] = static_cast<std::uint32_t>(w.edge_cell.size());
            continue;
        }
        for (std::size_t j = 0; j < sub_rays; ++j) {
            const std::size_t h = k * sub_rays + j;
            if (!w.hits.hit(h)) {
                w.target[j] = -1;
                continue;
            }
            if (w.hits.face[h] != last_face) {
                last_face = w.hits.face[h];
                last_part = static_cast<std::int64_t>(scene_->part_of_face(last_face));
            }
            w.target[j] = last_part;
        }
        sim_->edge_cells(w.target, w.edges);
        w.edge_cell.insert(w.edge_cell.end(), w.edges.begin(), w.edges.end());
        w.edge_start[k + 1] = static_cast<std::uint32_t>(w.edge_cell.size());
    }
    if (w.edge_cell.empty()) {
        return;
    }
    w.probe_rays.resize(w.edge_cell.size() * probes);
    w.probe_origins.resize(probes);
    w.probe_dirs.resize(probes);
    for (std::size_t k = 0; k < w.pulse_count; ++k) {
        const std::size_t c = k * sub_rays;  // the centre sub-ray (on the jittered axis)
        const Vec3d o{w.rays.ox[c], w.rays.oy[c], w.rays.oz[c]};
        const Vec3d d{w.rays.dx[c], w.rays.dy[c], w.rays.dz[c]};
        for (std::uint32_t e = w.edge_start[k]; e < w.edge_start[k + 1]; ++e) {
            sim_->probe_rays(o, d, w.edge_cell[e], w.probe_origins, w.probe_dirs);
            for (std::size_t p = 0; p < probes; ++p) {
                w.probe_rays.set(e * probes + p, w.probe_origins[p], w.probe_dirs[p],
                                 w.rays.tmin[c], w.rays.tmax[c]);
            }
        }
    }
}

bool SurveyPhysics::one_face_samples(BlockWork& w, std::size_t k, FaceCache& cache) const {
    const std::size_t sub_rays = this->sub_rays();
    const std::size_t h0 = k * sub_rays;
    const std::uint32_t face = w.hits.face[h0];
    if (face == kNoFace || w.edge_start[k] != w.edge_start[k + 1] ||
        !one_face(w.hits.face.data() + h0, sub_rays)) {
        return false;
    }
    // The facts as sub_ray_hit finds them for the first sub-ray (the others find them cached).
    const RayBatch& r = w.rays;
    const double t0 = w.hits.t[h0];
    const Vec3d at = Vec3d{r.ox[h0], r.oy[h0], r.oz[h0]} + Vec3d{r.dx[h0], r.dy[h0], r.dz[h0]} * t0;
    const FaceFacts& f = face_facts(face, at, w.pulses.time_s[k], cache);
    const Material& m = *f.material;
    if (!f.flat || m.pattern.kind != AlbedoPatternKind::uniform) {
        return false;
    }
    // make_sub_ray_hit's fields, each sub-ray's range and incidence on the face's normal.
    const double n = length(f.normal);
    std::vector<BeamSample>& samples = w.response.samples;
    samples.resize(sub_rays);
    w.sample_face.assign(sub_rays, face);
    for (std::size_t j = 0; j < sub_rays; ++j) {
        const std::size_t h = h0 + j;
        const Vec3d d{r.dx[h], r.dy[h], r.dz[h]};
        BeamSample& s = samples[j];
        s.hit.range_m = static_cast<double>(w.hits.t[h]);
        s.hit.cos_incidence = cos_incidence_of(f.normal, n, d);
        s.hit.albedo = m.reflectance;
        s.hit.specular_weight = m.specular_weight;
        s.hit.specular_exponent = m.specular_exponent;
        sim_->set_cell_sample(s, j);
    }
    return true;
}

void SurveyPhysics::simulate(BlockWork& w, std::size_t k, FaceCache& cache) const {
    const std::size_t sub_rays = this->sub_rays();
    const std::size_t probes = sim_->probes_per_cell();
    std::vector<BeamSample>& samples = w.response.samples;
    if (one_face_samples(w, k, cache)) {
        sim_->simulate_samples(seed_, w.first + k, samples, w.response);
        return;
    }
    samples.clear();
    w.sample_face.clear();
    std::uint32_t e = w.edge_start[k];
    for (std::size_t j = 0; j < sub_rays; ++j) {
        const std::size_t h = k * sub_rays + j;
        const SubRayHit hit = sub_ray_hit(w.rays, w.hits, h, w.pulses.time_s[k], cache);
        w.sample_face.push_back(w.hits.face[h]);
        if (e == w.edge_start[k + 1] || w.edge_cell[e] != j) {
            samples.push_back(sim_->cell_sample(hit, j));
            continue;
        }
        samples.push_back(sim_->edge_sample(hit, j));
        for (std::size_t p = e * probes; p < (e + 1) * probes; ++p) {
            samples.push_back(sim_->edge_sample(
                sub_ray_hit(w.probe_rays, w.probe_hits, p, w.pulses.time_s[k], cache), j));
            w.sample_face.push_back(w.probe_hits.face[p]);
        }
        ++e;
    }
    // simulate_samples reads the samples and writes the rest of the response.
    sim_->simulate_samples(seed_, w.first + k, samples, w.response);
}

void SurveyPhysics::run(BlockWork& w, const Backend& backend) const {
    const std::size_t max_returns = this->max_returns();
    find_edges(w);
    if (!w.edge_cell.empty()) {
        w.probe_hits.resize(w.probe_rays.size());
        backend.intersect(w.probe_rays, 0, w.probe_rays.size(), w.probe_hits, w.this_thread);
        if (moving != nullptr) {
            trace_moving_probes(w);
        }
    }
    FaceCache cache;  // the faces the block's pulses met
    for (std::size_t k = 0; k < w.pulse_count; ++k) {
        simulate(w, k, cache);
        if (keeps_waveforms()) {
            keep_waveform(w, k);
        }
        const std::size_t n = std::min(w.response.returns.size(), max_returns);
        for (std::size_t r = 0; r < n; ++r) {
            w.returns[k * max_returns + r] = w.response.returns[r];
            const std::uint32_t sample = w.response.returns[r].sub_ray;
            // The weather's echo: no face of the scene, facing the beam.
            const bool medium = w.response.returns[r].weather != WeatherEffect::none;
            w.return_face[k * max_returns + r] = medium ? kNoFace : w.sample_face[sample];
            w.return_cos_incidence[k * max_returns + r] =
                medium ? 1.0f : static_cast<float>(w.response.samples[sample].hit.cos_incidence);
        }
        w.return_count[k] = static_cast<std::uint8_t>(n);
    }
}

void SurveyPhysics::trace_moving_probes(BlockWork& w) const {
    const std::size_t probes = sim_->probes_per_cell();
    w.probe_time.resize(w.probe_rays.size());
    for (std::size_t k = 0; k < w.pulse_count; ++k) {
        std::fill(w.probe_time.begin() + w.edge_start[k] * probes,
                  w.probe_time.begin() + w.edge_start[k + 1] * probes, w.pulses.time_s[k]);
    }
    moving->intersect(w.probe_rays, 0, w.probe_rays.size(), w.probe_time, w.moving_frame,
                      w.probe_hits);
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
