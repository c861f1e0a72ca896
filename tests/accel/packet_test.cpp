// The BVH backend's packets (8 lanes with AVX2, 16 with AVX-512) against its single-ray walk:
// the same nearest hit, bit for bit (t, face, u, v), on random, coherent, grazing and
// edge/vertex rays; and a divergent beam's sub-rays traced as packets.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

struct PacketSetting {
    BvhTraceConfig trace;
    std::string name;
};

/// Every packet width this CPU has, each forced on every ray and as the backend chooses.
std::vector<PacketSetting> packet_settings() {
    std::vector<PacketSetting> all;
    for (const int lanes : {8, 16}) {
        for (const BvhPackets mode : {BvhPackets::always, BvhPackets::automatic}) {
            const BvhTraceConfig trace{mode, lanes};
            if (bvh_packet_lanes(trace) == lanes) {
                all.push_back({trace, std::to_string(lanes) + " lanes" +
                                          (mode == BvhPackets::always ? ", every ray" : "")});
            }
        }
    }
    if (all.empty()) {
        std::printf("[  NOTE    ] this CPU has no AVX2: the packet kernels were not run\n");
    }
    return all;
}

/// The bits of every field of hit i.
bool same_bits(const HitBatch& a, const HitBatch& b, std::size_t i) {
    return a.face[i] == b.face[i] &&
           std::bit_cast<std::uint32_t>(a.t[i]) == std::bit_cast<std::uint32_t>(b.t[i]) &&
           std::bit_cast<std::uint32_t>(a.u[i]) == std::bit_cast<std::uint32_t>(b.u[i]) &&
           std::bit_cast<std::uint32_t>(a.v[i]) == std::bit_cast<std::uint32_t>(b.v[i]);
}

/// Traces `rays` one at a time and in every packet setting; every hit must be the same bits.
/// Returns the single-ray hits.
HitBatch expect_same_as_single_rays(const TriangleMesh& mesh, const RayBatch& rays,
                                    const std::string& what) {
    ThreadPool pool(2);
    BackendConfig single;
    single.bvh_trace.packets = BvhPackets::off;
    const HitBatch want = make_backend(BackendKind::bvh, mesh, pool, single)->intersect(rays, pool);
    for (const PacketSetting& s : packet_settings()) {
        BackendConfig config;
        config.bvh_trace = s.trace;
        const HitBatch got =
            make_backend(BackendKind::bvh, mesh, pool, config)->intersect(rays, pool);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!same_bits(want, got, i) && ++differ <= 3) {
                ADD_FAILURE() << what << ", " << s.name << ": ray " << i << " single (t "
                              << want.t[i] << ", face " << want.face[i] << ", u " << want.u[i]
                              << ", v " << want.v[i] << ") packet (t " << got.t[i] << ", face "
                              << got.face[i] << ", u " << got.u[i] << ", v " << got.v[i] << ")";
            }
        }
        EXPECT_EQ(differ, 0u) << what << ", " << s.name << ": of " << rays.size() << " rays";
    }
    return want;
}

std::size_t hit_count(const HitBatch& h) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        n += h.hit(i) ? 1 : 0;
    }
    return n;
}

/// An airborne line scanner over `mesh` (a terrain): pulses along x at `height` above its top,
/// swept across y by +-30 degrees (a sawtooth), each pulse `sub` sub-rays in a cone of
/// `half_angle_rad` (a centre ray and rings), in the survey's order: pulse by pulse.
RayBatch airborne_rays(const TriangleMesh& mesh, std::size_t pulses, int sub, double half_angle_rad,
                       double height) {
    const Aabb b = mesh.bounds();
    RayBatch rays;
    rays.reserve(pulses * static_cast<std::size_t>(sub));
    const double cy = 0.5 * (double(b.lo.y) + double(b.hi.y));
    for (std::size_t k = 0; k < pulses; ++k) {
        const double f = double(k) / double(pulses);
        const Vec3d o{double(b.lo.x) + f * double(b.hi.x - b.lo.x), cy, double(b.hi.z) + height};
        const double phase = std::fmod(double(k) / 500.0, 1.0);
        const double angle = (2.0 * phase - 1.0) * 0.5236;
        const Vec3d axis{0.0, std::sin(angle), -std::cos(angle)};
        const Vec3d u = normalize(cross(axis, Vec3d{1, 0, 0}));
        const Vec3d v = cross(axis, u);
        for (int j = 0; j < sub; ++j) {
            const int ring = j == 0 ? 0 : (j <= 6 ? 1 : 2);
            const int in_ring = j == 0 ? 1 : (ring == 1 ? 6 : 12);
            const double phi = 2.0 * 3.141592653589793 * double(j) / double(in_ring);
            const double r = half_angle_rad * double(ring) / 2.0;
            rays.push_back(o, normalize(axis + u * (r * std::cos(phi)) + v * (r * std::sin(phi))));
        }
    }
    return rays;
}

/// Rays along the plane of random faces through a point of each (tilted by at most ~1e-4 rad
/// out of it, either way), from a few face sizes back: they graze the face and its neighbours.
RayBatch grazing_rays(const TriangleMesh& mesh, std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::uniform_int_distribution<std::size_t> pick(0, mesh.faces.size() - 1);
    RayBatch rays;
    while (rays.size() < n) {
        const Face& f = mesh.faces[pick(rng)];
        const Vec3d a(mesh.vertices[f[0]]), b(mesh.vertices[f[1]]), c(mesh.vertices[f[2]]);
        const Vec3d nrm = cross(b - a, c - a);
        if (dot(nrm, nrm) == 0.0) {
            continue;
        }
        const Vec3d nz = normalize(nrm);
        const double s = uni(rng), t = uni(rng) * (1.0 - s);
        const Vec3d p = a + (b - a) * s + (c - a) * t;
        const Vec3d in_plane = normalize((b - a) * (uni(rng) - 0.5) + (c - a) * (uni(rng) - 0.5));
        const Vec3d d = normalize(in_plane + nz * ((uni(rng) - 0.5) * 2e-4));
        const double back = 4.0 * length(b - a) + 1e-3;
        rays.push_back(p - d * back, d);
    }
    return rays;
}

/// From `inside` a closed mesh through every vertex and every edge's midpoint, in mesh order.
RayBatch vertex_and_edge_rays(const TriangleMesh& mesh, const Vec3d& inside) {
    RayBatch rays;
    for (const auto& p : mesh.vertices) {
        rays.push_back(inside, normalize(Vec3d(p) - inside));
    }
    for (const auto& f : mesh.faces) {
        for (std::size_t k = 0; k < 3; ++k) {
            const Vec3d a(mesh.vertices[f[k]]), b(mesh.vertices[f[(k + 1) % 3]]);
            rays.push_back(inside, normalize((a + b) * 0.5 - inside));
        }
    }
    return rays;
}

TEST(PacketTrace, RandomRaysMatchSingleRays) {
    const auto path = test::shared_data("meshes/small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh bunny = load_mesh(path);
    const RayBatch rays = test::rays_toward(bunny.bounds(), test::heavy_scale(300000), 11, 10);
    const HitBatch h = expect_same_as_single_rays(bunny, rays, "bunny random");
    EXPECT_GT(hit_count(h), rays.size() / 10);
}

TEST(PacketTrace, CoherentBeamsMatchSingleRays) {
    // The airborne survey's rays: 19 sub-rays of a 0.5 mrad beam (the divergence survey), and
    // one ray per pulse (neighbouring pulses in a packet), over the SRTM-like terrain.
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh terrain = load_mesh(path);
    const double height = 0.5 * length(Vec3d(terrain.bounds().extent()));
    const RayBatch beams = airborne_rays(terrain, test::heavy_scale(60000), 19, 2.5e-4, height);
    const HitBatch hb = expect_same_as_single_rays(terrain, beams, "terrain 19 sub-rays");
    EXPECT_GT(hit_count(hb), beams.size() * 3 / 4);
    const RayBatch pulses = airborne_rays(terrain, test::heavy_scale(600000), 1, 0.0, height);
    const HitBatch hp = expect_same_as_single_rays(terrain, pulses, "terrain pulses");
    EXPECT_GT(hit_count(hp), pulses.size() * 3 / 4);
}

TEST(PacketTrace, ShuffledRaysFromInsideAllHitAndMatchSingleRays) {
    // Rays from inside a closed sphere in every direction, in a random order: every stage is
    // sorted (its keys descend often; three radix passes of the group and both coordinates),
    // stages of odd sizes too (the sort's two halves and its tail), and every ray must come back
    // with a hit, its own (a ray lost or traced twice by the sort leaves a slot unhit or wrong).
    const TriangleMesh sphere = test::make_icosphere(4, 2.0f);
    std::mt19937_64 rng(21);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    for (const std::size_t n : {std::size_t{1024 * 3 + 517}, std::size_t{1023}, std::size_t{33}}) {
        RayBatch rays;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3d o{jitter(rng), jitter(rng), jitter(rng)};
            rays.push_back(o, normalize(Vec3d{gauss(rng), gauss(rng), gauss(rng)}));
        }
        const HitBatch h = expect_same_as_single_rays(sphere, rays, "shuffled from inside");
        EXPECT_EQ(hit_count(h), n) << n << " rays: some escaped or were not traced";
    }
}

TEST(PacketTrace, GrazingRaysMatchSingleRays) {
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh terrain = load_mesh(path);
    const RayBatch rays = grazing_rays(terrain, test::heavy_scale(300000), 12);
    const HitBatch h = expect_same_as_single_rays(terrain, rays, "terrain grazing");
    EXPECT_GT(hit_count(h), rays.size() / 2);
    const TriangleMesh sphere = test::make_icosphere(5, 2.0f);
    const RayBatch on_sphere = grazing_rays(sphere, test::heavy_scale(200000), 13);
    expect_same_as_single_rays(sphere, on_sphere, "icosphere grazing");
}

TEST(PacketTrace, SharedEdgesAndVerticesMatchSingleRaysAndNeverLeak) {
    // Rays exactly through the shared vertices and edges of closed meshes, from inside (in mesh
    // order, so neighbouring rays share a packet), and axis-aligned rays exactly through the
    // float vertices and edges of a grid (the double-precision edge case of the test).
    for (const auto& [mesh, inside, what] :
         {std::tuple{test::make_icosphere(5, 3.0f), Vec3d{0, 0, 0}, "icosphere"},
          std::tuple{test::make_icosphere(4, 1.0f), Vec3d{0.1, -0.2, 0.05}, "icosphere-offset"}}) {
        const RayBatch rays = vertex_and_edge_rays(mesh, inside);
        const HitBatch h = expect_same_as_single_rays(mesh, rays, what);
        EXPECT_EQ(hit_count(h), rays.size()) << what << ": rays escaped";
    }
    const TriangleMesh grid = test::make_grid(64);
    RayBatch rays;
    for (int j = 0; j <= 256; ++j) {
        for (int i = 0; i <= 256; ++i) {
            rays.push_back({0.25 * i, 0.25 * j, 10.0}, {0, 0, -1});
            rays.push_back({0.25 * i, 0.25 * j, -10.0}, {0, 0, 1});
            rays.push_back({0.25 * i, 0.25 * j, 10.0}, normalize(Vec3d{1e-3, 2e-3, -1}));
        }
    }
    const HitBatch h = expect_same_as_single_rays(grid, rays, "grid");
    for (std::size_t i = 0; i < rays.size(); i += 3) {
        ASSERT_TRUE(h.hit(i) && h.hit(i + 1)) << "grid ray " << i << " leaked";
        EXPECT_EQ(h.t[i], 10.0f);
    }
}

/// A 64-beam spinning scanner (HDL-64-like: a vertical fan from -24.9 to +2 degrees, 0.18
/// degrees of azimuth per firing) 2.1 m over the demo scene's terrain, driving along y = -10
/// from x = -30 to 30, in the survey's order: firing by firing, the 64 beams of a firing side
/// by side (neighbouring rays of a packet are then far apart on the ground unless the packets
/// are made of one beam's neighbouring firings).
RayBatch spinning_fan_rays(std::size_t firings) {
    constexpr double kDeg = 3.141592653589793 / 180.0;
    RayBatch rays;
    rays.reserve(firings * 64);
    for (std::size_t k = 0; k < firings; ++k) {
        const double x = -30.0 + 60.0 * double(k) / double(firings);
        const Vec3d o{x, -10.0, demo_terrain_height(x, -10.0) + 2.1};
        const double az = std::fmod(double(k) * 0.18, 360.0) * kDeg;
        for (int b = 0; b < 64; ++b) {
            const double el = (-24.9 + 26.9 * double(b) / 63.0) * kDeg;
            rays.push_back(
                o, {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)});
        }
    }
    return rays;
}

TEST(PacketTrace, SpinningScannerRaysMatchSingleRaysAndBruteForce) {
    // The car survey's scene (terrain, vehicles, an occluding plane: one mesh) and its kind of
    // rays: the packets are made of beams regrouped by direction, whatever order they come in.
    const Scene scene = make_demo_scene();
    ASSERT_TRUE(scene.geometry.is_single_mesh());
    const TriangleMesh& mesh = scene.geometry.meshes[0];
    const RayBatch rays = spinning_fan_rays(test::heavy_scale(8000));
    const HitBatch h = expect_same_as_single_rays(mesh, rays, "spinning fan");
    EXPECT_GT(hit_count(h), rays.size() / 2);
    // The single-ray walk against brute force on a sample, so the packets are checked against
    // an independent answer too.
    RayBatch sample;
    std::vector<std::size_t> picked;
    for (std::size_t i = 0; i < rays.size(); i += 2477) {
        sample.push_back(rays.origin(i), rays.direction(i));
        picked.push_back(i);
    }
    ThreadPool pool(2);
    const HitBatch want = make_backend(BackendKind::brute, mesh, pool)->intersect(sample, pool);
    for (std::size_t s = 0; s < picked.size(); ++s) {
        EXPECT_EQ(want.face[s], h.face[picked[s]]) << "ray " << picked[s];
        EXPECT_EQ(want.t[s], h.t[picked[s]]) << "ray " << picked[s];
    }
}

/// `mesh` cut into `parts` meshes of consecutive faces, each with the vertices its faces use
/// (the same float corners), each placed once with the identity: a scene of several meshes,
/// face IDs those of `mesh`.
SceneGeometry cut_into_meshes(const TriangleMesh& mesh, std::size_t parts) {
    SceneGeometry g;
    const std::size_t n = mesh.faces.size();
    for (std::size_t p = 0; p < parts; ++p) {
        TriangleMesh part;
        std::vector<std::uint32_t> index(mesh.vertices.size(), kNoFace);
        for (std::size_t f = p * n / parts; f < (p + 1) * n / parts; ++f) {
            Face face = mesh.faces[f];
            for (auto& v : face) {
                if (index[v] == kNoFace) {
                    index[v] = static_cast<std::uint32_t>(part.vertices.size());
                    part.vertices.push_back(mesh.vertices[v]);
                }
                v = index[v];
            }
            part.faces.push_back(face);
        }
        g.add_instance(g.add_mesh(std::move(part)), Affine3{});
    }
    return g;
}

TEST(PacketTrace, SeveralMeshesMatchBruteForceBitForBitAndNeverLeak) {
    // A closed sphere made of three meshes (their shared edges are where the parts meet), from
    // inside through every vertex and edge, and random rays: the BVH over a scene of several
    // meshes placed with the identity traces them as one mesh, in packets; every hit must be
    // brute force's (which tests every face of the flattened scene), bit for bit.
    const TriangleMesh ico = test::make_icosphere(4, 1.0f);
    const SceneGeometry g = cut_into_meshes(ico, 3);
    ASSERT_FALSE(g.is_single_mesh());
    RayBatch rays = vertex_and_edge_rays(ico, {0.1, -0.2, 0.05});
    const std::size_t closed = rays.size();
    const RayBatch random = test::rays_toward(ico.bounds(), 20000, 21, 7);
    for (std::size_t i = 0; i < random.size(); ++i) {
        rays.push_back(random.origin(i), random.direction(i));
    }
    ThreadPool pool(2);
    const HitBatch want = make_backend(BackendKind::brute, g, pool)->intersect(rays, pool);
    std::vector<BvhTraceConfig> traces{BvhTraceConfig{BvhPackets::off, 0}};
    for (const PacketSetting& s : packet_settings()) {
        traces.push_back(s.trace);
    }
    for (const BvhTraceConfig& trace : traces) {
        BackendConfig config;
        config.bvh_trace = trace;
        const HitBatch got = make_backend(BackendKind::bvh, g, pool, config)->intersect(rays, pool);
        std::size_t differ = 0, leaked = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            differ += same_bits(want, got, i) ? 0 : 1;
            leaked += i < closed && !got.hit(i) ? 1 : 0;
        }
        EXPECT_EQ(differ, 0u) << bvh_packet_lanes(trace) << " lanes, of " << rays.size();
        EXPECT_EQ(leaked, 0u) << bvh_packet_lanes(trace) << " lanes, of " << closed;
    }
}

TEST(PacketTrace, WidestPacketsAreTheDefault) {
    const int widest = bvh_packet_lanes(BvhTraceConfig{});
    EXPECT_TRUE(widest == 1 || widest == 8 || widest == 16);
    EXPECT_EQ(bvh_packet_lanes(BvhTraceConfig{BvhPackets::off, 0}), 1);
    EXPECT_EQ(bvh_packet_lanes(BvhTraceConfig{BvhPackets::automatic, 4}), 1);
    if (widest >= 8) {
        EXPECT_EQ(bvh_packet_lanes(BvhTraceConfig{BvhPackets::always, 8}), 8);
    }
}

}  // namespace
}  // namespace beamtrace
