// Embree: the limit (EmbreeLimit: a minimal loop calling rtcIntersect1 directly over the same
// RayBatch, on our ThreadPool) against our Embree backend and our BVH on the 1 M-triangle
// terrain / 512x512 nadir pinhole of bench_trace.cpp, and a 10^8-triangle instanced scene (1440
// Stanford bunnies) traced by the two-level BVH and Embree with peak RSS. Hit counts are checked
// before timing. Compare ratios with --benchmark_filter='BM_Embree.*Terrain'; run the instanced
// cases in their own process (--benchmark_filter=BM_EmbreeInstanced) so peak RSS is theirs alone.
#ifdef BEAMTRACE_HAVE_EMBREE
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <thread>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "bench_scenes.hpp"
#include "harness/embree_limit.hpp"

namespace bt = beamtrace;

namespace {

using bt::bench::nadir_rays;
using bt::bench::terrain_1m;

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "benchmark check failed: %s\n", what.c_str());
    std::exit(1);
}

unsigned threads_arg(const benchmark::State& state) {
    return static_cast<unsigned>(state.range(0));
}

std::size_t count_hits(const std::vector<std::uint32_t>& face) {
    std::size_t n = 0;
    for (auto f : face) {
        n += f != bt::kNoFace ? 1 : 0;
    }
    return n;
}

void check_terrain_once() {
    static bool done = false;
    if (done) {
        return;
    }
    done = true;
    bt::ThreadPool pool(0);
    const bt::EmbreeLimit raw(terrain_1m(), pool.size());
    std::vector<std::uint32_t> faces;
    raw.trace(nadir_rays(), bt::EmbreeCall::single, faces, pool);
    const std::size_t limit_hits = count_hits(faces);
    if (limit_hits != nadir_rays().size()) {
        fail("raw Embree: a nadir ray missed");
    }
    for (auto kind : {bt::BackendKind::embree, bt::BackendKind::bvh}) {
        const auto backend = bt::make_backend(kind, terrain_1m(), pool);
        const bt::HitBatch hits = backend->intersect(nadir_rays(), pool);
        if (count_hits(hits.face) != limit_hits) {
            fail(std::string(bt::to_string(kind)) + ": hit count differs from raw Embree");
        }
    }
}

void BM_EmbreeLimitTerrain(benchmark::State& state) {
    check_terrain_once();
    bt::ThreadPool pool(threads_arg(state));
    const bt::EmbreeLimit raw(terrain_1m(), pool.size());
    std::vector<std::uint32_t> faces;
    for (auto _ : state) {
        raw.trace(nadir_rays(), bt::EmbreeCall::single, faces, pool);
        benchmark::DoNotOptimize(faces.data());
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(nadir_rays().size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

template <bt::BackendKind Kind>
void BM_EmbreeCompareTerrain(benchmark::State& state) {
    check_terrain_once();
    bt::ThreadPool pool(threads_arg(state));
    const auto backend = bt::make_backend(Kind, terrain_1m(), pool);
    bt::HitBatch hits;
    hits.resize(nadir_rays().size());
    for (auto _ : state) {
        backend->intersect(nadir_rays(), 0, nadir_rays().size(), hits, pool);
        benchmark::DoNotOptimize(hits.t.data());
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(nadir_rays().size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

/// 1440 bunnies (40 x 36, 0.25 m apart; 69 451 triangles each: 100.0 M triangles).
const bt::SceneGeometry* bunnies() {
    static const bt::SceneGeometry* scene = []() -> const bt::SceneGeometry* {
        const std::filesystem::path path =
            std::filesystem::path(BEAMTRACE_SHARED_DATA_DIR) / "meshes/small/stanford-bunny.obj";
        if (!std::filesystem::exists(path)) {
            return nullptr;
        }
        auto* g = new bt::SceneGeometry;  // lives for the whole run
        const std::uint32_t m = g->add_mesh(bt::load_mesh(path));
        for (int j = 0; j < 36; ++j) {
            for (int i = 0; i < 40; ++i) {
                bt::Affine3 t;
                t.translation = {0.25 * i, 0.25 * j, 0.0};
                g->add_instance(m, t);
            }
        }
        return g;
    }();
    return scene;
}

/// 512 x 512 rays straight down over the whole array.
const bt::RayBatch& bunny_rays() {
    static const bt::RayBatch rays = [] {
        bt::RayBatch r;
        const bt::Aabb b = bunnies()->bounds();
        for (int j = 0; j < 512; ++j) {
            for (int i = 0; i < 512; ++i) {
                const double x = b.lo.x + (b.hi.x - b.lo.x) * (i + 0.5) / 512.0;
                const double y = b.lo.y + (b.hi.y - b.lo.y) * (j + 0.5) / 512.0;
                r.push_back({x, y, double(b.hi.z) + 1.0}, {0.0, 0.0, -1.0});
            }
        }
        return r;
    }();
    return rays;
}

template <bt::BackendKind Kind>
void BM_EmbreeInstanced(benchmark::State& state) {
    if (bunnies() == nullptr) {
        state.SkipWithError("stanford-bunny.obj not found");
        return;
    }
    bt::ThreadPool pool(threads_arg(state));
    const auto backend = bt::make_backend(Kind, *bunnies(), pool);
    const bt::HitBatch check = backend->intersect(bunny_rays(), pool);
    const std::size_t hits = count_hits(check.face);
    if (hits < bunny_rays().size() / 10) {
        fail("instanced bunnies: too few hits");
    }
    bt::HitBatch out;
    out.resize(bunny_rays().size());
    for (auto _ : state) {
        backend->intersect(bunny_rays(), 0, bunny_rays().size(), out, pool);
        benchmark::DoNotOptimize(out.t.data());
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(bunny_rays().size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
    state.counters["triangles"] = static_cast<double>(bunnies()->triangle_count());
    state.counters["hits"] = static_cast<double>(hits);
    state.counters["peak_rss_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
}

void embree_thread_args(benchmark::internal::Benchmark* b) {
    b->Arg(1);
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    if (hw > 1) {
        b->Arg(static_cast<int>(hw));
    }
    b->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_EmbreeLimitTerrain)->Apply(embree_thread_args)->MinTime(1.0);
BENCHMARK(BM_EmbreeCompareTerrain<bt::BackendKind::embree>)
    ->Name("BM_EmbreeBackendTerrain")
    ->Apply(embree_thread_args)
    ->MinTime(1.0);
BENCHMARK(BM_EmbreeCompareTerrain<bt::BackendKind::bvh>)
    ->Name("BM_EmbreeBvhTerrain")
    ->Apply(embree_thread_args)
    ->MinTime(1.0);
BENCHMARK(BM_EmbreeInstanced<bt::BackendKind::bvh>)
    ->Name("BM_EmbreeInstanced/bvh")
    ->Apply(embree_thread_args)
    ->MinTime(1.0);
BENCHMARK(BM_EmbreeInstanced<bt::BackendKind::embree>)
    ->Name("BM_EmbreeInstanced/embree")
    ->Apply(embree_thread_args)
    ->MinTime(1.0);

}  // namespace
#endif  // BEAMTRACE_HAVE_EMBREE
