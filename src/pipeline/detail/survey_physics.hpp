// The survey's physics stage: each pulse's sub-ray hits become its returns (and, when kept,
// its sampled waveform), with the scene's materials.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/physics/material.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/scene/scene.hpp"
#include "pipeline/detail/survey_block.hpp"

namespace beamtrace::detail {

class SurveyPhysics {
  public:
    /// `sim` and `scene` must outlive the stage; `materials` are the scene's (survey_materials).
    SurveyPhysics(const PulseSimulator& sim, const Scene& scene, std::vector<Material> materials,
                  std::uint64_t seed);

    [[nodiscard]] std::size_t sub_rays() const { return sim_->sub_ray_count(); }
    [[nodiscard]] std::size_t max_returns() const {
        return static_cast<std::size_t>(sim_->config().max_returns);
    }
    [[nodiscard]] bool keeps_waveforms() const { return sim_->config().keep_waveform; }

    /// Fills w.returns, w.return_face and w.return_count from w.rays and w.hits, tracing the
    /// probes of edge cells with `backend` on the caller's thread; appends the waveforms to
    /// w.points when they are kept. Thread-safe (const): blocks run on many threads at once.
    void run(BlockWork& w, const Backend& backend) const;
    /// The scene's moving instances (nullptr: none), traced with the probes at their pulse's time.
    const MovingInstances* moving = nullptr;

  private:
    /// What the samples that meet one face share: its part and the part's material, and its
    /// normal where that does not vary over the face (not a sphere's). An airborne beam's 19
    /// sub-rays meet 1 to 4 triangles, and the next pulses mostly the same ones.
    struct FaceFacts {
        std::uint32_t face = kNoFace;
        const ScenePart* part = nullptr;
        const Material* material = nullptr;
        bool flat = false;    ///< normal holds for every point of the face
        bool still = false;   ///< not a moving instance's: normal holds at every time
        double time_s = 0.0;  ///< the time normal was computed at (a moving face's holds then)
        Vec3d normal{0, 0, 0};
    };
    /// The facts of the last faces a block's pulses met: a still face's hold for every pulse, a
    /// moving face's for pulses at its time_s.
    struct FaceCache {
        std::array<FaceFacts, 8> faces;
        std::size_t next = 0;
    };
    /// The facts of `face` (hit at `point_m` at `time_s`), from `cache` or computed into it.
    const FaceFacts& face_facts(std::uint32_t face, const Vec3d& point_m, double time_s,
                                FaceCache& cache) const;
    /// The edge cells of every pulse of the block and their probe rays (w.edge_*, w.probe_*).
    void find_edges(BlockWork& w) const;
    /// The SubRayHit of ray h of `rays` (hits[h] a hit).
    [[nodiscard]] SubRayHit sub_ray_hit(const RayBatch& rays, const HitBatch& hits, std::size_t h,
                                        double time_s, FaceCache& cache) const;
    /// Traces the probes on the moving instances too (each at its pulse's time).
    void trace_moving_probes(BlockWork& w) const;
    /// Pulse k's samples when all its sub-rays met one flat face of a uniform albedo and no cell
    /// is an edge (almost every pulse over a terrain): the facts shared, made as simulate would
    /// make them, bit for bit; false (samples not made) otherwise.
    bool one_face_samples(BlockWork& w, std::size_t k, FaceCache& cache) const;
    /// Pulse k's beam samples (w.response.samples, w.sample_face), simulated into w.response.
    void simulate(BlockWork& w, std::size_t k, FaceCache& cache) const;
    void keep_waveform(BlockWork& w, std::size_t k) const;

    const PulseSimulator* sim_;
    const Scene* scene_;
    std::vector<Material> materials_;
    std::uint64_t seed_;
};

}  // namespace beamtrace::detail
