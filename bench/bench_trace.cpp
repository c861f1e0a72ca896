// Every backend of the registry this build has (BVH, k-d tree, brute force, Embree, ...): build
// rate (triangles/s) of our trees and trace rate (rays/s) on a 1 M-triangle terrain seen by a
// 512x512 nadir pinhole, all in one run so the figures compare as ratios. Results are checked
// (every ray hits, backends agree) before anything is timed.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <thread>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/accel/backend_registry.hpp"
#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/accel/kdtree.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "bench_scenes.hpp"

namespace bt = beamtrace;

namespace {

using bt::bench::nadir_rays;
using bt::bench::terrain_1m;

/// A subset of the nadir rays (every k-th), for the brute-force baseline.
bt::RayBatch every_kth(const bt::RayBatch& rays, std::size_t k) {
    bt::RayBatch sub;
    for (std::size_t i = 0; i < rays.size(); i += k) {
        sub.push_back(rays.origin(i), rays.direction(i));
    }
    return sub;
}

[[noreturn]] void fail(const char* what) {
    std::fprintf(stderr, "benchmark check failed: %s\n", what);
    std::exit(1);
}

/// Every backend agrees with brute force on a subset, and every nadir ray hits.
void check_once() {
    static bool done = false;
    if (done) {
        return;
    }
    done = true;
    bt::ThreadPool pool(0);
    const auto& mesh = terrain_1m();
    const bt::RayBatch sub = every_kth(nadir_rays(), 1024);
    const auto oracle = bt::make_backend(bt::BackendKind::brute, mesh, pool)->intersect(sub, pool);
    for (const auto kind : bt::usable_backends()) {
        if (kind == bt::BackendKind::brute) {
            continue;
        }
        const auto backend = bt::make_backend(kind, mesh, pool);
        const auto got = backend->intersect(sub, pool);
        for (std::size_t i = 0; i < sub.size(); ++i) {
            // The same face, or (a ray through a shared edge, Embree's own triangle test) the
            // same range.
            if (got.hit(i) != oracle.hit(i) ||
                (got.face[i] != oracle.face[i] &&
                 std::fabs(got.t[i] - oracle.t[i]) > 1e-5f * oracle.t[i])) {
                fail("backend disagrees with brute force");
            }
        }
        const auto all = backend->intersect(nadir_rays(), pool);
        for (std::size_t i = 0; i < all.size(); ++i) {
            if (!all.hit(i)) {
                fail("a nadir ray missed the terrain");
            }
        }
    }
}

unsigned threads_arg(const benchmark::State& state) {
    return static_cast<unsigned>(state.range(0));
}

void BM_BuildBvh(benchmark::State& state) {
    const auto& mesh = terrain_1m();
    bt::ThreadPool pool(threads_arg(state));
    for (auto _ : state) {
        bt::Bvh bvh = bt::build_bvh(mesh, {}, pool);
        benchmark::DoNotOptimize(bvh.nodes.data());
    }
    state.counters["triangles/s"] = benchmark::Counter(
        static_cast<double>(mesh.triangle_count()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_BuildKdTree(benchmark::State& state) {
    const auto& mesh = terrain_1m();
    const auto config =
        state.range(0) != 0 ? bt::KdTreeBuildConfig::report() : bt::KdTreeBuildConfig{};
    for (auto _ : state) {
        bt::KdTree tree = bt::build_kdtree(mesh, config);
        benchmark::DoNotOptimize(tree.nodes.data());
    }
    state.counters["triangles/s"] = benchmark::Counter(
        static_cast<double>(mesh.triangle_count()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Trace(benchmark::State& state, bt::BackendKind kind, bool report_rules) {
    check_once();
    const auto& mesh = terrain_1m();
    bt::ThreadPool pool(threads_arg(state));
    bt::BackendConfig config;
    if (report_rules) {
        config.kdtree = bt::KdTreeBuildConfig::report();
    }
    const auto backend = bt::make_backend(kind, mesh, pool, config);
    // Brute force traces every 1024th ray only (1 M tests per ray); rays/s stays comparable.
    const bt::RayBatch rays =
        kind == bt::BackendKind::brute ? every_kth(nadir_rays(), 1024) : nadir_rays();
    bt::HitBatch hits;
    hits.resize(rays.size());
    for (auto _ : state) {
        backend->intersect(rays, 0, rays.size(), hits, pool);
        benchmark::DoNotOptimize(hits.t.data());
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays.size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

void thread_args(benchmark::internal::Benchmark* b) {
    b->Arg(1);
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    if (hw > 1) {
        b->Arg(static_cast<int>(hw));
    }
    b->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_BuildBvh)->Apply(thread_args)->MinTime(1.0);
BENCHMARK(BM_BuildKdTree)
    ->ArgName("report_rules")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
/// BM_Trace/<name> for every backend of the registry this build has, in table order (brute
/// force once: it is the baseline), and BM_Trace/kdtree_report_rules.
int register_trace_benchmarks() {
    for (const bt::BackendEntry& e : bt::backend_registry()) {
        if (!e.usable()) {
            continue;
        }
        const std::string name = "BM_Trace/" + std::string(e.name);
        auto* b =
            benchmark::RegisterBenchmark(name.c_str(), BM_Trace, e.kind, false)->Apply(thread_args);
        if (e.kind == bt::BackendKind::brute) {
            b->Iterations(1);
        } else {
            b->MinTime(1.0);
        }
        if (e.kind == bt::BackendKind::kdtree) {
            benchmark::RegisterBenchmark("BM_Trace/kdtree_report_rules", BM_Trace, e.kind, true)
                ->Apply(thread_args)
                ->MinTime(1.0);
        }
    }
    return 0;
}

[[maybe_unused]] const int kTraceBenchmarks = register_trace_benchmarks();

}  // namespace

BENCHMARK_MAIN();
