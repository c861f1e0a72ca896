// The BVH packets' interval culling (packet_kernel.inl: a coherent packet walks the tree as one
// frustum, bounded by its lanes' least and greatest origins and inverse directions), against
// the single-ray walk bit for bit (t, face, u, v) and against brute force: narrow cones of
// sub-rays, packets whose lanes differ in direction sign or have zero direction components,
// rays skimming the planes of node boxes, packets of one lane, and 1 and 2 threads alike.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

bool same_bits(const HitBatch& a, std::size_t i, const HitBatch& b, std::size_t j) {
    return a.face[i] == b.face[j] &&
           std::bit_cast<std::uint32_t>(a.t[i]) == std::bit_cast<std::uint32_t>(b.t[j]) &&
           std::bit_cast<std::uint32_t>(a.u[i]) == std::bit_cast<std::uint32_t>(b.u[j]) &&
           std::bit_cast<std::uint32_t>(a.v[i]) == std::bit_cast<std::uint32_t>(b.v[j]);
}

/// Every packet width this CPU has, forced on every ray and as the backend chooses.
std::vector<BvhTraceConfig> packet_traces() {
    std::vector<BvhTraceConfig> all;
    for (const int lanes : {8, 16}) {
        for (const BvhPackets mode : {BvhPackets::always, BvhPackets::automatic}) {
            if (bvh_packet_lanes(BvhTraceConfig{mode, lanes}) == lanes) {
                all.push_back(BvhTraceConfig{mode, lanes});
            }
        }
    }
    return all;
}

/// The BVH backends of one mesh: single rays, every packet setting, and brute force.
struct Tracers {
    ThreadPool one{1}, two{2};
    std::unique_ptr<Backend> single, brute;
    std::vector<std::pair<int, std::unique_ptr<Backend>>> packets;

    explicit Tracers(const TriangleMesh& mesh) {
        BackendConfig off;
        off.bvh_trace.packets = BvhPackets::off;
        single = make_backend(BackendKind::bvh, mesh, one, off);
        brute = make_backend(BackendKind::brute, mesh, two);
        for (const BvhTraceConfig& trace : packet_traces()) {
            BackendConfig config;
            config.bvh_trace = trace;
            packets.emplace_back(trace.lanes, make_backend(BackendKind::bvh, mesh, one, config));
        }
    }
};

/// Traces `rays` one at a time (1 thread) and in every packet setting on 1 and 2 threads: every
/// hit must be the same bits. With `brute`, the single rays must also be brute force's, bit for
/// bit, so the packets are checked against an independent answer. Returns the hits.
HitBatch expect_exact(Tracers& tr, const RayBatch& rays, const std::string& what, bool brute) {
    const HitBatch want = tr.single->intersect(rays, tr.one);
    if (brute) {
        const HitBatch b = tr.brute->intersect(rays, tr.two);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            differ += same_bits(want, i, b, i) ? 0 : 1;
        }
        EXPECT_EQ(differ, 0u) << what << ": single rays against brute force, of " << rays.size();
    }
    for (const auto& [lanes, backend] : tr.packets) {
        for (ThreadPool* pool : {&tr.one, &tr.two}) {
            const HitBatch got = backend->intersect(rays, *pool);
            std::size_t differ = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                if (!same_bits(want, i, got, i) && ++differ <= 3) {
                    ADD_FAILURE() << what << ", " << lanes << " lanes, " << pool->size()
                                  << " threads: ray " << i << " single (t " << want.t[i]
                                  << ", face " << want.face[i] << ") packet (t " << got.t[i]
                                  << ", face " << got.face[i] << ")";
                }
            }
            EXPECT_EQ(differ, 0u) << what << ", " << lanes << " lanes, of " << rays.size();
        }
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

/// `sub` rays of a cone of half-angle `half_angle_rad` about `axis` from one origin: a centre ray
/// and rings of 6 and 12 (a divergent beam's sub-rays).
void push_cone(RayBatch& rays, const Vec3d& o, const Vec3d& axis, int sub, double half_angle_rad) {
    const Vec3d w = normalize(axis);
    const Vec3d u = normalize(cross(w, std::fabs(w.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0}));
    const Vec3d v = cross(w, u);
    for (int j = 0; j < sub; ++j) {
        const int ring = j == 0 ? 0 : (j <= 6 ? 1 : 2);
        const int in_ring = j == 0 ? 1 : (ring == 1 ? 6 : 12);
        const double phi = 2.0 * 3.141592653589793 * double(j) / double(in_ring);
        const double r = half_angle_rad * double(ring) / 2.0;
        rays.push_back(o, normalize(w + u * (r * std::cos(phi)) + v * (r * std::sin(phi))));
    }
}

TEST(PacketFrustum, SubRayConesMatchSingleRaysAndBruteForce) {
    // Narrow cones (0.25 mrad and 5 mrad) of 19 sub-rays from random points around the bunny
    // and over the terrain toward random points of it: each cone is a packet of one origin.
    const auto bunny_path = test::shared_data("meshes/small/stanford-bunny.obj");
    const auto terrain_path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(bunny_path);
    BEAMTRACE_REQUIRE_FILE(terrain_path);
    for (const auto& [path, what] : {std::pair{bunny_path, "bunny"}, {terrain_path, "terrain"}}) {
        const TriangleMesh mesh = load_mesh(path);
        const RayBatch centres = test::rays_toward(mesh.bounds(), 400, 31);
        RayBatch rays;
        for (std::size_t i = 0; i < centres.size(); ++i) {
            push_cone(rays, centres.origin(i), centres.direction(i), 19, i % 2 ? 2.5e-4 : 5e-3);
        }
        Tracers tr(mesh);
        const HitBatch h = expect_exact(tr, rays, std::string(what) + " cones", true);
        EXPECT_GT(hit_count(h), rays.size() / 3) << what;
    }
}

TEST(PacketFrustum, MixedSignsAndZeroDirectionComponentsMatchBruteForce) {
    // Near-nadir fans over a grid whose lanes (a) cross x = 0 or y = 0 in direction (mixed signs
    // in one packet), (b) have an exactly zero x component (+0 and -0 alike: infinite inverse
    // directions of either sign), some from origins exactly on the grid's vertex lines (the
    // planes of node boxes), (c) mix zero and nonzero components in one packet, and (d) have
    // components so small that their inverses overflow toward infinity.
    const TriangleMesh grid = test::make_grid(64);
    RayBatch rays;
    for (int row = 0; row < 64; ++row) {
        const double y = 0.5 + row;
        for (int k = -16; k < 16; ++k) {
            const double s = 1e-3 * (k + 0.5);
            rays.push_back({20.0 + 0.37 * row, y, 7.0}, normalize(Vec3d{s, 0.3 * s, -1}));  // (a)
            const double zx = k % 2 == 0 ? 0.0 : -0.0;
            rays.push_back({double(row % 64), y + 0.01 * k, 5.0}, {zx, s, -1});    // (b)
            rays.push_back({30.5, y, 3.0}, {k % 3 == 0 ? 0.0 : 1e-4 * k, s, -1});  // (c)
            rays.push_back({10.25, y, 9.0}, {1e-41 * (k + 20), 1e-40, -1});        // (d)
        }
    }
    Tracers tr(grid);
    const HitBatch h = expect_exact(tr, rays, "grid fans", true);
    EXPECT_EQ(hit_count(h), rays.size()) << "rays through a grid below them escaped";
}

TEST(PacketFrustum, RaysSkimmingBoxPlanesMatchBruteForce) {
    // Rays in the planes of node boxes: horizontal rays at the height of a flat grid (z = 2, no
    // z motion: every box's slab is met exactly on its plane) and just above and below it, and
    // rays along the grid lines x = i and y = j (the planes that split it), both ways.
    const TriangleMesh grid = test::make_grid(32, 2.0f);
    RayBatch rays;
    for (int i = 0; i <= 32; ++i) {
        for (const double dz : {0.0, 1e-7, -1e-7}) {
            for (int k = 0; k < 8; ++k) {
                const double s = 1e-3 * k;
                rays.push_back({-1.0, double(i), 2.0 + dz}, normalize(Vec3d{1, s, 0}));
                rays.push_back({33.0, double(i), 2.0 + dz}, normalize(Vec3d{-1, -s, 0}));
                rays.push_back({double(i), -1.0, 2.0 + dz}, normalize(Vec3d{0, 1, -s}));
            }
        }
        for (int k = 0; k < 16; ++k) {
            rays.push_back({double(i), 0.5 + 2.0 * k, 4.0}, normalize(Vec3d{0, 1e-3 * k, -1}));
            rays.push_back({0.5 + 2.0 * k, double(i), 4.0}, normalize(Vec3d{1e-3 * k, 0, -1}));
        }
    }
    Tracers tr(grid);
    const HitBatch h = expect_exact(tr, rays, "skimming rays", true);
    EXPECT_GE(hit_count(h), 33u * 32u) << "the rays down along the grid lines";
    // Grazing the terrain's own faces, in coherent fans (8 rays 1e-5 rad apart).
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh terrain = load_mesh(path);
    std::mt19937_64 rng(41);
    std::uniform_int_distribution<std::size_t> pick(0, terrain.faces.size() - 1);
    RayBatch graze;
    while (graze.size() < 40000) {
        const Face& f = terrain.faces[pick(rng)];
        const Vec3d a(terrain.vertices[f[0]]), b(terrain.vertices[f[1]]), c(terrain.vertices[f[2]]);
        const Vec3d n = cross(b - a, c - a);
        if (dot(n, n) == 0.0) {
            continue;
        }
        const Vec3d d = normalize(b - a);
        const Vec3d p = (a + b + c) * (1.0 / 3.0);
        for (int k = 0; k < 8; ++k) {
            const Vec3d dk = normalize(d + normalize(n) * (1e-5 * (k - 4)));
            graze.push_back(p - dk * (3.0 * length(b - a)), dk);
        }
    }
    Tracers tt(terrain);
    expect_exact(tt, graze, "terrain grazing fans", false);
}

TEST(PacketFrustum, ExactFrustaThroughVerticesAndEdgesMatchBruteForce) {
    // Every ray 16 times in a row: the packets are one ray each, so their frusta are that ray's
    // slab test exactly, and rays through the grid's vertices and edge midpoints (hits on the
    // boundaries of leaf boxes, shared by faces of several leaves: the tie goes to the lowest
    // face) find the nearest face only if no box on their way is culled by a rounding.
    const TriangleMesh grid = test::make_grid(16, 2.0f);
    RayBatch rays;
    std::mt19937_64 rng(47);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (int j = 1; j < 32; ++j) {  // inside the grid: a ray at its rim may miss
        for (int i = 1; i < 32; ++i) {
            const Vec3d target{0.5 * i, 0.5 * j, 2.0};
            const Vec3d o = target + Vec3d{uni(rng), uni(rng), 1.0 + 0.5 * (uni(rng) + 1.0)};
            for (int k = 0; k < 16; ++k) {
                rays.push_back(o, normalize(target - o));
            }
        }
    }
    Tracers tr(grid);
    const HitBatch h = expect_exact(tr, rays, "exact frusta", true);
    EXPECT_EQ(hit_count(h), rays.size()) << "rays through the grid's vertices escaped";
}

TEST(PacketFrustum, LineScansAcrossNadirSplitBySignMatchBruteForce) {
    // A sawtooth line scan across nadir (y changes sign mid-line, and the scan wraps from +30 to
    // -30 degrees inside a stage, so stages are sorted), pulse by pulse: the x component flips
    // sign from pulse to pulse, is +0 or -0 in some, and tmax cuts some rays short of the grid.
    // Packets are made of rays of one sign per axis; each must match the single rays and brute
    // force bit for bit, and so must batches of odd sizes (partial packets and stages).
    const TriangleMesh grid = test::make_grid(48);
    RayBatch rays;
    for (int k = 0; k < 3000; ++k) {
        const double angle = (2.0 * std::fmod(k / 700.0, 1.0) - 1.0) * 0.5236;
        const double sx = k % 5 == 0 ? (k % 2 == 0 ? 0.0 : -0.0) : (k % 2 == 0 ? 1e-7 : -1e-7);
        const Vec3d o{4.0 + 0.013 * k, 24.0, 30.0};
        const double tmax = k % 7 == 3 ? 25.0 : std::numeric_limits<double>::infinity();
        rays.push_back(o, normalize(Vec3d{sx, std::sin(angle), -std::cos(angle)}), 0.5 * (k % 3),
                       tmax);
    }
    Tracers tr(grid);
    const HitBatch h = expect_exact(tr, rays, "line scan across nadir", true);
    EXPECT_GT(hit_count(h), rays.size() / 2);
    EXPECT_LT(hit_count(h), rays.size()) << "the rays cut short by tmax";
    for (const std::size_t n : {1u, 17u, 1023u, 1041u}) {
        RayBatch part;
        for (std::size_t i = 0; i < n; ++i) {
            part.push_back(rays.origin(i), rays.direction(i), rays.tmin[i], rays.tmax[i]);
        }
        expect_exact(tr, part, std::to_string(n) + " rays across nadir", false);
    }
}

TEST(PacketFrustum, LineScanStagesLeftInOrderMatchBruteForce) {
    // Line scans whose x component keeps one sign (an airborne scanner's), so a stage's keys rise
    // but for the scan's turns: a sawtooth of 300 pulses a line turns at most 4 times in a stage
    // of 1024 (left in order, cut into packets at the turns), one of 100 more often (sorted), and
    // a triangle wave falls for a whole line (sorted). Each must match the single rays and brute
    // force bit for bit.
    const TriangleMesh grid = test::make_grid(48);
    Tracers tr(grid);
    for (const int line : {300, 100, -300}) {
        RayBatch rays;
        for (int k = 0; k < 3000; ++k) {
            const double phase = std::fmod(k / double(std::abs(line)), 2.0);
            const double s = line > 0 ? std::fmod(phase, 1.0) : (phase < 1.0 ? phase : 2.0 - phase);
            const double angle = (2.0 * s - 1.0) * 0.5236;
            const Vec3d o{4.0 + 0.013 * k, 24.0, 30.0};
            rays.push_back(o, normalize(Vec3d{0.02, std::sin(angle), -std::cos(angle)}));
        }
        const HitBatch h = expect_exact(tr, rays, "line scan of " + std::to_string(line), true);
        EXPECT_EQ(hit_count(h), rays.size()) << "line scan of " << line;
    }
}

TEST(PacketFrustum, WideFansOverReliefMatchBruteForce) {
    // A spinning scanner's beams over bumpy ground: a packet is one beam's 16 firings (48 mrad
    // wide), whose frustum reaches many leaves that only some lanes, or none, enter (at a leaf
    // only the lanes whose own slab test passes it test its faces).
    TriangleMesh ground = test::make_grid(48);
    for (Vec3f& v : ground.vertices) {
        v.z = 0.4f * std::sin(0.7f * v.x) * std::cos(0.9f * v.y);
    }
    RayBatch rays;
    for (int firing = 0; firing < 600; ++firing) {
        const double azimuth = 0.003 * firing;
        for (int beam = 0; beam < 8; ++beam) {
            const double elevation = -0.05 - 0.05 * beam;
            rays.push_back(Vec3d{24.0, 24.0, 2.0},
                           Vec3d{std::cos(elevation) * std::cos(azimuth),
                                 std::cos(elevation) * std::sin(azimuth), std::sin(elevation)});
        }
    }
    Tracers tr(ground);
    const HitBatch h = expect_exact(tr, rays, "wide fans over relief", true);
    EXPECT_GT(hit_count(h), rays.size() * 3 / 4);
}

TEST(PacketFrustum, PacketsOfOneLaneAndPartialPacketsMatchSingleRays) {
    // Batches of 1, 2, 15, 17 and 33 rays: the last packet of a group has one or a few lanes
    // (the others copy lane 0 and must bound nothing).
    const auto path = test::shared_data("meshes/small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh bunny = load_mesh(path);
    Tracers tr(bunny);
    const RayBatch pool = test::rays_toward(bunny.bounds(), 2000, 43);
    for (const std::size_t n : {1u, 2u, 15u, 17u, 33u}) {
        for (std::size_t first = 0; first + n <= pool.size(); first += 97) {
            RayBatch rays;
            // One cone per batch: coherent, so the packet takes the culled walk.
            for (std::size_t i = 0; i < n; ++i) {
                const Vec3d d = pool.direction(first) + pool.direction(first + i) * 1e-3;
                rays.push_back(pool.origin(first), normalize(d));
            }
            expect_exact(tr, rays, std::to_string(n) + " rays from " + std::to_string(first),
                         false);
        }
    }
}

}  // namespace
}  // namespace beamtrace
