// The BVH backend's nearest-hit trace on a survey's own rays (the car HDL-64 and the airborne
// SRTM surveys, first 256 k pulses) against our Embree backend, one thread, packets off and on
// (the widest lanes, and 8: the AVX2 kernel on an AVX-512 CPU): the A/B figure for the packet
// walk's grouping of rays; and the 19-sub-ray survey's rays as beams (Backend::intersect_beams,
// what the survey calls: a pulse's sub-rays walk the tree as one frustum), checked bit for bit
// against the rays' hits. The hits are checked against Embree's (watertight, the same faces),
// and the packets' against the single-ray walk's bit for bit, before anything is timed. CPU
// time is the figure to read on a shared machine.
#include <benchmark/benchmark.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/accel/backend_registry.hpp"
#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/scene_builder.hpp"

namespace bt = beamtrace;

namespace {

struct SurveyRays {
    bt::Scene scene;
    bt::RayBatch rays;
};

const SurveyRays& survey_rays(const std::string& file) {
    static std::map<std::string, std::unique_ptr<SurveyRays>> cache;
    auto& slot = cache[file];
    if (!slot) {
        const auto path = std::filesystem::path(BEAMTRACE_EXAMPLES_DIR) / "surveys" / file;
        const bt::SurveySpec spec = bt::load_survey_spec(path);
        bt::ThreadPool pool(1);
        slot = std::make_unique<SurveyRays>();
        slot->scene =
            spec.scene_file.empty() ? bt::make_demo_scene() : bt::load_scene_file(spec.scene_file);
        // About 256 k rays: the 19-sub-ray survey's pulses are 19 rays each.
        const std::uint64_t pulses = file.find("divergence") != std::string::npos ? 13797 : 262144;
        slot->rays = bt::survey_rays(spec, 1, pulses, pool);
    }
    return *slot;
}

/// bvh_packets8: packets of 8 lanes (the AVX2 kernel) on a CPU that has AVX-512 too; bvh_beams:
/// the 19 sub-rays of a pulse as one beam.
enum class Mode { embree, bvh_single, bvh_packets, bvh_packets8, bvh_beams };

/// The survey's sub-rays a pulse (intersect_beams' beam) in `mode`.
constexpr std::size_t kBeamRays = 19;

/// Whether the beams' hits are the rays' own, bit for bit.
bool beams_match(const bt::Backend& backend, const bt::RayBatch& rays, const bt::HitBatch& want,
                 bt::ThreadPool& pool) {
    bt::HitBatch beams;
    beams.resize(rays.size());
    backend.intersect_beams(rays, 0, rays.size(), kBeamRays, beams, pool);
    return beams.t == want.t && beams.face == want.face && beams.u == want.u && beams.v == want.v;
}

/// Whether the packets' hits (`got`) are the single-ray walk's, bit for bit.
bool packets_match(const bt::SceneGeometry& geometry, const bt::RayBatch& rays,
                   const bt::HitBatch& got, bt::ThreadPool& pool) {
    bt::BackendConfig single;
    single.bvh_trace.packets = bt::BvhPackets::off;
    bt::HitBatch want;
    want.resize(rays.size());
    bt::make_backend(bt::BackendKind::bvh, geometry, pool, single)
        ->intersect(rays, 0, rays.size(), want, pool);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (std::bit_cast<std::uint32_t>(got.t[i]) != std::bit_cast<std::uint32_t>(want.t[i]) ||
            got.face[i] != want.face[i] ||
            std::bit_cast<std::uint32_t>(got.u[i]) != std::bit_cast<std::uint32_t>(want.u[i]) ||
            std::bit_cast<std::uint32_t>(got.v[i]) != std::bit_cast<std::uint32_t>(want.v[i])) {
            return false;
        }
    }
    return true;
}

void BM_SurveyRays(benchmark::State& state, const std::string& file, Mode mode) {
    const SurveyRays& s = survey_rays(file);
    bt::ThreadPool pool(1);
    bt::BackendConfig config;
    if (mode == Mode::bvh_single) {
        config.bvh_trace.packets = bt::BvhPackets::off;
    }
    if (mode == Mode::bvh_packets8) {
        config.bvh_trace.lanes = 8;
        if (bt::bvh_packet_lanes(config.bvh_trace) != 8) {
            state.SkipWithError("no AVX2 on this CPU");
            return;
        }
    }
    if (mode == Mode::embree && !bt::backend_entry(bt::BackendKind::embree).usable()) {
        state.SkipWithError("no Embree in this build");
        return;
    }
    const auto kind = mode == Mode::embree ? bt::BackendKind::embree : bt::BackendKind::bvh;
    const auto backend = bt::make_backend(kind, s.scene.geometry, pool, config);
    bt::HitBatch hits;
    hits.resize(s.rays.size());
    backend->intersect(s.rays, 0, s.rays.size(), hits, pool);
    if (mode != Mode::embree && bt::backend_entry(bt::BackendKind::embree).usable()) {
        bt::HitBatch want;
        want.resize(s.rays.size());
        bt::make_backend(bt::BackendKind::embree, s.scene.geometry, pool)
            ->intersect(s.rays, 0, s.rays.size(), want, pool);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < s.rays.size(); ++i) {
            differ += want.face[i] != hits.face[i] ? 1 : 0;
        }
        // Ties on shared edges may pick another face; a handful of rays at most.
        if (differ > s.rays.size() / 10000) {
            state.SkipWithError("the BVH's faces differ from Embree's");
            return;
        }
    }
    const bool packets = mode == Mode::bvh_packets || mode == Mode::bvh_packets8;
    if (packets && !packets_match(s.scene.geometry, s.rays, hits, pool)) {
        state.SkipWithError("the packets' hits differ from the single-ray walk's");
        return;
    }
    const bool beams = mode == Mode::bvh_beams;
    if (beams && !beams_match(*backend, s.rays, hits, pool)) {
        state.SkipWithError("the beams' hits differ from the rays'");
        return;
    }
    for (auto _ : state) {
        if (beams) {
            backend->intersect_beams(s.rays, 0, s.rays.size(), kBeamRays, hits, pool);
        } else {
            backend->intersect(s.rays, 0, s.rays.size(), hits, pool);
        }
        benchmark::DoNotOptimize(hits.face.data());
    }
    state.counters["rays/s"] =
        benchmark::Counter(static_cast<double>(s.rays.size()) * double(state.iterations()),
                           benchmark::Counter::kIsRate);
}

void args(benchmark::internal::Benchmark* b) {
    b->Unit(benchmark::kMillisecond)->MinTime(1.0);
}

BENCHMARK_CAPTURE(BM_SurveyRays, car_embree, std::string("car_hdl64.yaml"), Mode::embree)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, car_bvh_single, std::string("car_hdl64.yaml"), Mode::bvh_single)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, car_bvh_packets, std::string("car_hdl64.yaml"), Mode::bvh_packets)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, car_bvh_packets8, std::string("car_hdl64.yaml"),
                  Mode::bvh_packets8)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, airborne_19_subrays_embree,
                  std::string("airborne_srtm_divergence.yaml"), Mode::embree)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, airborne_19_subrays_bvh_packets,
                  std::string("airborne_srtm_divergence.yaml"), Mode::bvh_packets)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, airborne_19_subrays_bvh_beams,
                  std::string("airborne_srtm_divergence.yaml"), Mode::bvh_beams)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, airborne_embree, std::string("airborne_srtm.yaml"), Mode::embree)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, airborne_bvh_single, std::string("airborne_srtm.yaml"),
                  Mode::bvh_single)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, airborne_bvh_packets, std::string("airborne_srtm.yaml"),
                  Mode::bvh_packets)
    ->Apply(args);
BENCHMARK_CAPTURE(BM_SurveyRays, airborne_bvh_packets8, std::string("airborne_srtm.yaml"),
                  Mode::bvh_packets8)
    ->Apply(args);

}  // namespace
