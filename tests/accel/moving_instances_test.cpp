// Moving instances traced at each ray's time (accel/moving_instances.hpp) against the oracle: the
// brute-force backend over the scene frozen at that time (every instance placed, flattened), and a
// closed form (a box face sliding along its normal).
#include "beamtrace/accel/moving_instances.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/geometry/primitives.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

struct MovingScene {
    SceneGeometry still;  ///< what stays; its faces come first
    std::vector<TriangleMesh> meshes;
    std::vector<RigidMotion> motions;
    std::vector<MovingInstance> moving;
};

/// A still ground grid and sphere, and five moving icospheres: sliding, spinning about an
/// off-centre pivot, mirrored and stretched, and on keyframes.
MovingScene make_scene() {
    MovingScene s;
    s.still.append_flat(test::make_grid(16, -3.0f));
    s.still.append_flat(make_icosphere({4, 4, 0}, 1.0, 2));
    const std::uint32_t first = static_cast<std::uint32_t>(s.still.face_count());
    s.meshes = s.still.meshes;  // same mesh indices: mesh 0 is the still one
    s.meshes.push_back(make_icosphere({0, 0, 0}, 1.0, 2));
    const auto sphere = static_cast<std::uint32_t>(s.meshes.size() - 1);
    const auto faces = static_cast<std::uint32_t>(s.meshes[sphere].triangle_count());
    RigidMotion slide;
    slide.pivot_m = {-6, 0, 0};
    slide.velocity_mps = {6, 0, 0};
    RigidMotion spin;
    spin.pivot_m = {0, 3, 0};
    spin.spin_axis = normalize(Vec3d{0.3, 0, 1});
    spin.spin_rate_rad_s = 2.0;
    RigidMotion keys;
    keys.keys.push_back({0.2, {-3, -3, 0}, Quat{}});
    keys.keys.push_back({0.9, {3, -2, 1}, Quat::from_rpy({0.5, 0.2, 1.5})});
    keys.keys.push_back({1.6, {0, -4, 0}, Quat::from_rpy({-0.5, 0.0, 3.0})});
    s.motions = {slide, spin, keys};
    Affine3 stretch;
    stretch.linear.m = {{{-1.2, 0, 0}, {0, 0.6, 0}, {0, 0, 0.9}}};  // mirrors
    Affine3 shifted;
    shifted.translation = {2, 0, 0};  // 2 m from the spin's pivot
    s.moving = {{sphere, first, 0, Affine3{}, {0, 0, 0}},
                {sphere, first + faces, 1, shifted, {0, 0, 0}},
                {sphere, first + 2 * faces, 2, stretch, {0, 0, 0}},
                {sphere, first + 3 * faces, 0, stretch, {0, -6, 1}},
                {sphere, first + 4 * faces, 1, Affine3{}, {-4, 0, 0}}};
    return s;
}

/// The scene at time t as plain instances (what the oracle traces).
SceneGeometry frozen(const MovingScene& s, double t) {
    SceneGeometry g;
    for (const auto& m : s.meshes) {
        g.add_mesh(m);
    }
    for (const auto& inst : s.still.instances) {
        g.add_instance(inst.mesh, inst.to_world);
    }
    for (const auto& mi : s.moving) {
        g.add_instance(mi.mesh, mi.to_world(s.motions[mi.motion].at(t)));
    }
    return g;
}

/// make_scene() and six runs of copies that share a motion that never turns (runs of an array:
/// the first four traced as groups by a backend, the others flattened into the top level): two
/// or three small spheres each, sliding, on keys that only move, one stretched and mirrored.
MovingScene make_scene_with_runs() {
    MovingScene s = make_scene();
    const auto sphere = static_cast<std::uint32_t>(s.meshes.size() - 1);
    const auto faces = static_cast<std::uint32_t>(s.meshes[sphere].triangle_count());
    auto next_face = s.moving.back().first_face + faces;
    Affine3 small;
    small.linear.m = {{{0.4, 0, 0}, {0, 0.4, 0}, {0, 0, 0.4}}};
    Affine3 mirrored = small;
    mirrored.linear.m[0][0] = -0.5;
    for (int run = 0; run < 6; ++run) {
        RigidMotion how;
        if (run % 3 == 2) {  // keys that only move the run (one attitude throughout)
            const Quat q = Quat::from_rpy({0.1 * run, 0.0, 0.3});
            how.keys.push_back({0.1, {-2.0 + run, 5, 0}, q});
            how.keys.push_back({1.1, {2.0 - run, 4, 1}, q});
            how.keys.push_back({1.7, {0.0, 6, -1}, q});
        } else {
            how.pivot_m = {-5.0 + run, -5.0 + 0.5 * run, 0.5};
            how.velocity_mps = {3.0 - run, 1.0 + 0.5 * run, 0.2 * run};
        }
        const auto motion = static_cast<std::uint32_t>(s.motions.size());
        s.motions.push_back(how);
        for (int copy = 0; copy < 2 + run % 2; ++copy) {
            const Vec3d offset{1.5 * copy, 0.8 * run - 2.0, 0.3 * copy};
            s.moving.push_back({sphere, next_face, motion, run == 1 ? mirrored : small, offset});
            next_face += faces;
        }
    }
    return s;
}

/// Traces rays at 8 times in [0, 2] s through `s` and checks each hit against the brute-force
/// backend over the scene frozen at the ray's time; returns the hits on faces from `from_face`.
std::size_t expect_brute_force_hits(const MovingScene& s, BackendKind groups,
                                    std::uint32_t from_face = 0, std::size_t n = 3000) {
    ThreadPool pool(2);
    const auto still = make_backend(BackendKind::bvh, s.still, pool);
    const MovingInstances moving(s.meshes, s.moving, s.motions, BvhBuildConfig{}, pool, groups);
    const Aabb box{{-8, -8, -3}, {8, 8, 3}};
    const RayBatch rays = test::rays_toward(box, n, 7);
    const double t0 = 0.0, t1 = 2.0;
    std::vector<double> times(n);
    for (std::size_t i = 0; i < n; ++i) {
        times[i] = t0 + (t1 - t0) * static_cast<double>(i % 8) / 7.0;  // 8 distinct times
    }
    HitBatch hits;
    hits.resize(n);
    still->intersect(rays, 0, n, hits, pool);
    MovingFrame frame;
    moving.prepare(t0, t1, frame, pool);
    moving.intersect(rays, 0, n, times, frame, hits);
    std::size_t on_moving = 0, face_differs = 0, from = 0;
    for (int k = 0; k < 8; ++k) {
        const SceneGeometry g = frozen(s, times[static_cast<std::size_t>(k)]);
        const auto brute = make_backend(BackendKind::brute, g, pool);
        const HitBatch want = brute->intersect(rays, pool);
        for (std::size_t i = static_cast<std::size_t>(k); i < n; i += 8) {
            EXPECT_EQ(hits.hit(i), want.hit(i)) << "ray " << i;
            if (!want.hit(i) || !hits.hit(i)) {
                continue;
            }
            EXPECT_NEAR(hits.t[i], want.t[i], 1e-4f * (1.0f + want.t[i])) << "ray " << i;
            from += want.face[i] >= from_face ? 1 : 0;
            on_moving += want.face[i] >= s.moving.front().first_face ? 1 : 0;
            face_differs += hits.face[i] != want.face[i] ? 1 : 0;
        }
    }
    EXPECT_GT(on_moving, n / 20) << "the moving spheres are hit";
    EXPECT_LE(face_differs, n / 500) << "only rays through shared edges may pick a neighbour";
    return from;
}

TEST(MovingInstances, NearestHitsEqualBruteForceOverTheSceneFrozenAtEachRaysTime) {
    (void)expect_brute_force_hits(make_scene(), BackendKind::bvh);
}

TEST(MovingInstances, RunsSharingAMotionEqualBruteForceWithEitherBackend) {
    const MovingScene s = make_scene_with_runs();
    const std::uint32_t first_run_face = make_scene().moving.back().first_face + 1;
    for (const BackendKind groups : {BackendKind::bvh, BackendKind::embree}) {
        SCOPED_TRACE(std::string(to_string(groups)));
        EXPECT_GT(expect_brute_force_hits(s, groups, first_run_face, 1000), 50u)
            << "the runs' spheres are hit";
    }
}

TEST(MovingInstances, ASlidingFaceIsMetWhereItIsAtTheRaysTime) {
    // A unit square facing -x, sliding along +x at 25 m/s from x = 10; rays along +x at 1 ms steps.
    TriangleMesh square = make_square({0, 0, 0}, {-1, 0, 0}, 1.0);
    std::vector<TriangleMesh> meshes{square};
    RigidMotion slide;
    slide.pivot_m = {10, 0, 0};
    slide.velocity_mps = {25, 0, 0};
    const std::vector<RigidMotion> motions{slide};
    const std::vector<MovingInstance> inst{{0, 0, 0, Affine3{}, {0, 0, 0}}};
    ThreadPool pool(1);
    const MovingInstances moving(meshes, inst, motions, BvhBuildConfig{}, pool);
    RayBatch rays;
    std::vector<double> times;
    for (int i = 0; i < 100; ++i) {
        rays.push_back({0, 0.2, -0.1}, {1, 0, 0});
        times.push_back(1e-3 * i);
    }
    HitBatch hits;
    hits.resize(rays.size());
    MovingFrame frame;
    moving.prepare(0.0, 0.099, frame, pool);
    moving.intersect(rays, 0, rays.size(), times, frame, hits);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(hits.hit(i)) << i;
        EXPECT_NEAR(hits.t[i], 10.0 + 25.0 * times[i], 1e-5) << i;
    }
}

}  // namespace
}  // namespace beamtrace
