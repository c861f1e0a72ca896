// Exact spheres against icospheres: 32 x 32 balls (radius 0.4 m, 1 m apart) as exact spheres
// (one face each; Embree's native sphere geometry) or as instances of one subdivision-4 icosphere
// (5120 triangles), traced by 512 x 512 nadir rays with the BVH and Embree backends. Checked
// before timing: the two scenes' hit counts agree within 1 % and exact hits lie on their sphere.
// Compare the pairs with --benchmark_filter=BM_Spheres.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/accel/backend_registry.hpp"
#include "beamtrace/geometry/primitives.hpp"

namespace bt = beamtrace;

namespace {

constexpr int kSide = 32;
constexpr float kRadius = 0.4f;

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "benchmark check failed: %s\n", what.c_str());
    std::exit(1);
}

bt::Vec3d ball_centre(int i, int j) {
    return {1.0 * i, 1.0 * j, 0.0};
}

const bt::SceneGeometry& ball_scene(bool exact) {
    static const bt::SceneGeometry* scenes[2] = {nullptr, nullptr};
    const bt::SceneGeometry*& s = scenes[exact ? 1 : 0];
    if (s == nullptr) {
        auto* g = new bt::SceneGeometry;  // lives for the whole run
        const std::uint32_t mesh =
            exact ? 0 : g->add_mesh(bt::make_icosphere({0, 0, 0}, kRadius, 4));
        for (int j = 0; j < kSide; ++j) {
            for (int i = 0; i < kSide; ++i) {
                if (exact) {
                    g->add_sphere(bt::Vec3f(ball_centre(i, j)), kRadius);
                } else {
                    bt::Affine3 t;
                    t.translation = ball_centre(i, j);
                    g->add_instance(mesh, t);
                }
            }
        }
        s = g;
    }
    return *s;
}

const bt::RayBatch& ball_rays() {
    static const bt::RayBatch rays = [] {
        bt::RayBatch r;
        for (int j = 0; j < 512; ++j) {
            for (int i = 0; i < 512; ++i) {
                const double x = -0.5 + kSide * (i + 0.5) / 512.0;
                const double y = -0.5 + kSide * (j + 0.5) / 512.0;
                r.push_back({x, y, 10.0}, {0.0, 0.0, -1.0});
            }
        }
        return r;
    }();
    return rays;
}

std::size_t hit_count(const bt::HitBatch& h) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        n += h.hit(i) ? 1 : 0;
    }
    return n;
}

void check_once(bt::BackendKind kind) {
    static bool done[4] = {false, false, false, false};
    if (done[static_cast<int>(kind)]) {
        return;
    }
    done[static_cast<int>(kind)] = true;
    bt::ThreadPool pool(0);
    const bt::HitBatch exact =
        bt::make_backend(kind, ball_scene(true), pool)->intersect(ball_rays(), pool);
    const bt::HitBatch ico =
        bt::make_backend(kind, ball_scene(false), pool)->intersect(ball_rays(), pool);
    const auto ne = static_cast<double>(hit_count(exact)), ni = static_cast<double>(hit_count(ico));
    // Nadir rays that pass within the radius of a centre, counted in the plane.
    double covered = 0;
    for (std::size_t i = 0; i < ball_rays().size(); ++i) {
        const double x = ball_rays().ox[i], y = ball_rays().oy[i];
        covered += std::hypot(x - std::round(x), y - std::round(y)) < kRadius ? 1.0 : 0.0;
    }
    if (std::fabs(ne - covered) > 0.001 * covered || std::fabs(ni - ne) > 0.01 * ne) {
        fail("spheres: " + std::to_string(ne) + " exact and " + std::to_string(ni) +
             " icosphere hits, expected about " + std::to_string(covered));
    }
    const bt::RayBatch& rays = ball_rays();
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!exact.hit(i)) {
            continue;
        }
        const bt::ExactSphere* s = ball_scene(true).sphere_of_face(exact.face[i]);
        const bt::Vec3d p = rays.origin(i) + rays.direction(i) * static_cast<double>(exact.t[i]);
        if (s == nullptr || std::fabs(length(p - bt::Vec3d(s->center)) - kRadius) > 1e-5) {
            fail("spheres: an exact hit is off its sphere");
        }
    }
}

/// Args: backend, exact (1) or icosphere (0), threads.
void BM_Spheres(benchmark::State& state) {
    const auto kind = static_cast<bt::BackendKind>(state.range(0));
    const bool exact = state.range(1) != 0;
    check_once(kind);
    bt::ThreadPool pool(static_cast<unsigned>(state.range(2)));
    const auto backend = bt::make_backend(kind, ball_scene(exact), pool);
    bt::HitBatch hits;
    hits.resize(ball_rays().size());
    for (auto _ : state) {
        backend->intersect(ball_rays(), 0, ball_rays().size(), hits, pool);
        benchmark::DoNotOptimize(hits.t.data());
    }
    state.SetLabel(std::string(bt::to_string(kind)) + (exact ? " exact" : " icosphere"));
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(ball_rays().size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

void sphere_args(benchmark::internal::Benchmark* b) {
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    for (const auto kind : bt::usable_backends()) {
        if (kind == bt::BackendKind::brute) {
            continue;  // the oracle: every ray against every triangle, not a contender
        }
        for (const int exact : {0, 1}) {
            b->Args({static_cast<int>(kind), exact, static_cast<int>(hw)});
        }
    }
    b->ArgNames({"backend", "exact", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_Spheres)->Apply(sphere_args)->MinTime(1.0);

}  // namespace
