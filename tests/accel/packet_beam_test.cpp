// Backend::intersect_beams (rays in beams of n sub-rays: with the BVH's packets a beam walks the
// tree as one frustum, lanes moving up and down an axis bounded on it by their own near
// distances) against the single-ray walk, bit for bit (t, face, u, v): airborne beams about the
// along-track plane, beams straight down an axis (zero direction components), beams through the
// shared vertices and edges of a grid and a closed sphere (ties), random beams of every size
// (beyond what one frustum takes too, and a last beam cut short), at 1 and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// The BVH settings beams are traced with: every packet width this CPU has (forced on every
/// ray and as the backend chooses), and single rays.
std::vector<BvhTraceConfig> beam_traces() {
    std::vector<BvhTraceConfig> all{BvhTraceConfig{BvhPackets::off, 0}};
    for (const int lanes : {8, 16}) {
        for (const BvhPackets mode : {BvhPackets::always, BvhPackets::automatic}) {
            if (bvh_packet_lanes(BvhTraceConfig{mode, lanes}) == lanes) {
                all.push_back(BvhTraceConfig{mode, lanes});
            }
        }
    }
    return all;
}

/// Traces `rays` one at a time, then in beams of `per_beam` with every setting at 1 and 2
/// threads (all of them, and from ray `skip` on); every hit must be the same bits. Returns the
/// single-ray hits.
HitBatch expect_beams_match(const TriangleMesh& mesh, const RayBatch& rays, std::size_t per_beam,
                            const std::string& what, std::size_t skip = 0) {
    ThreadPool one(1), two(2);
    BackendConfig single;
    single.bvh_trace.packets = BvhPackets::off;
    const HitBatch want = make_backend(BackendKind::bvh, mesh, one, single)->intersect(rays, one);
    for (const BvhTraceConfig& trace : beam_traces()) {
        BackendConfig config;
        config.bvh_trace = trace;
        const auto backend = make_backend(BackendKind::bvh, mesh, one, config);
        for (ThreadPool* pool : {&one, &two}) {
            HitBatch got;
            got.resize(rays.size());
            backend->intersect_beams(rays, skip, rays.size(), per_beam, got, *pool);
            std::size_t differ = 0;
            for (std::size_t i = skip; i < rays.size(); ++i) {
                const bool same = want.face[i] == got.face[i] &&
                                  std::bit_cast<std::uint32_t>(want.t[i]) ==
                                      std::bit_cast<std::uint32_t>(got.t[i]) &&
                                  std::bit_cast<std::uint32_t>(want.u[i]) ==
                                      std::bit_cast<std::uint32_t>(got.u[i]) &&
                                  std::bit_cast<std::uint32_t>(want.v[i]) ==
                                      std::bit_cast<std::uint32_t>(got.v[i]);
                if (!same && ++differ <= 3) {
                    ADD_FAILURE() << what << ", " << bvh_packet_lanes(trace) << " lanes, "
                                  << pool->size() << " threads: ray " << i << " single (t "
                                  << want.t[i] << ", face " << want.face[i] << ") beam (t "
                                  << got.t[i] << ", face " << got.face[i] << ")";
                }
            }
            EXPECT_EQ(differ, 0u) << what << ", " << bvh_packet_lanes(trace) << " lanes, "
                                  << pool->size() << " threads, of " << rays.size() - skip;
        }
    }
    return want;
}

/// How many rays of `h` hit a face.
std::size_t hit_count(const HitBatch& h) {
    return static_cast<std::size_t>(
        std::count_if(h.face.begin(), h.face.end(), [](std::uint32_t f) { return f != kNoFace; }));
}

/// A beam of `sub` sub-rays from `o` about `axis` (a centre ray and rings of 6 and 12, then
/// more of 18), the outermost ring at `half_angle_rad`.
void push_beam(RayBatch& rays, const Vec3d& o, const Vec3d& axis, int sub, double half_angle_rad) {
    const Vec3d side = std::fabs(axis.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    const Vec3d u = normalize(cross(axis, side));
    const Vec3d v = cross(axis, u);
    const int rings = sub <= 1 ? 1 : (sub <= 7 ? 1 : (sub <= 19 ? 2 : 3));
    for (int j = 0; j < sub; ++j) {
        const int ring = j == 0 ? 0 : (j <= 6 ? 1 : (j <= 18 ? 2 : 3));
        const int first = ring == 0 ? 0 : (ring == 1 ? 1 : (ring == 2 ? 7 : 19));
        const double phi =
            2.0 * 3.141592653589793 * double(j - first) / double(6 * ring + (ring == 0));
        const double r = half_angle_rad * double(ring) / double(rings);
        rays.push_back(o, normalize(axis + u * (r * std::cos(phi)) + v * (r * std::sin(phi))));
    }
}

TEST(PacketBeams, AirborneBeamsMatchSingleRays) {
    // The airborne survey's beams: flying along x level, so every beam's sub-rays move up and
    // down x; swept across y, through nadir (the centre ray straight down: zero components).
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh terrain = load_mesh(path);
    const Aabb b = terrain.bounds();
    const double height = 0.5 * length(Vec3d(b.extent()));
    for (const int sub : {19, 7}) {
        RayBatch rays;
        const std::size_t pulses = test::heavy_scale(20000);
        for (std::size_t k = 0; k < pulses; ++k) {
            const double f = double(k) / double(pulses);
            const Vec3d o{double(b.lo.x) + f * double(b.hi.x - b.lo.x),
                          0.5 * (double(b.lo.y) + double(b.hi.y)), double(b.hi.z) + height};
            // Through 0 exactly every 400 pulses (a nadir beam).
            const double angle = (double(k % 400) / 200.0 - 1.0) * 0.5236;
            push_beam(rays, o, Vec3d{0.0, std::sin(angle), -std::cos(angle)}, sub, 2.5e-4);
        }
        const HitBatch h =
            expect_beams_match(terrain, rays, static_cast<std::size_t>(sub), "airborne", 0);
        EXPECT_GT(hit_count(h), rays.size() * 3 / 4);
        expect_beams_match(terrain, rays, static_cast<std::size_t>(sub), "airborne skip",
                           static_cast<std::size_t>(sub) * 7);
    }
}

TEST(PacketBeams, BeamsThroughSharedEdgesAndVerticesMatchSingleRays) {
    // Sub-rays exactly through a grid's float vertices and edge midpoints, straight down and
    // slanted (ties between the faces sharing them), and from inside a closed sphere through a
    // vertex and the midpoints of its edges (no sub-ray may leak).
    const TriangleMesh grid = test::make_grid(32);
    RayBatch rays;
    for (int j = 0; j <= 64; ++j) {
        for (int i = 0; i <= 64; ++i) {
            const Vec3d o{0.5 * i + 0.25, 0.5 * j, 10.0};
            for (int s = 0; s < 19; ++s) {
                const Vec3d to{0.5 * i + 0.5 * (s % 3) - 0.5 + 0.25,
                               0.5 * j + 0.5 * (s / 3 % 3) - 0.5, 0.0};
                rays.push_back(o, s == 0 ? Vec3d{0, 0, -1} : normalize(to - o));
            }
        }
    }
    const HitBatch h = expect_beams_match(grid, rays, 19, "grid");
    EXPECT_GT(hit_count(h), rays.size() * 3 / 4);
    const TriangleMesh ico = test::make_icosphere(4, 1.0f);
    const Vec3d inside{0.1, -0.2, 0.05};
    RayBatch closed;
    for (const Face& f : ico.faces) {
        const Vec3d a(ico.vertices[f[0]]), b(ico.vertices[f[1]]), c(ico.vertices[f[2]]);
        for (const Vec3d& p :
             {a, (a + b) * 0.5, (a + c) * 0.5, b, c, (b + c) * 0.5, (a + b + c) * (1.0 / 3.0)}) {
            closed.push_back(inside, normalize(p - inside));
        }
    }
    const HitBatch hc = expect_beams_match(ico, closed, 7, "icosphere");
    EXPECT_EQ(hit_count(hc), closed.size()) << "sub-rays escaped";
}

TEST(PacketBeams, RandomBeamsOfEverySizeMatchSingleRays) {
    // Random origins around the bunny (runs of 8 beams from one), axes toward it, cones from 1e-5
    // to 0.4 rad (wider than one frustum takes: the packets or single rays then), beams of 2 to 130
    // sub-rays (many beams to a walk, one, and more than a walk takes: traced as packets), some
    // with their origins spread, the last beam cut short.
    const auto path = test::shared_data("meshes/small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh bunny = load_mesh(path);
    const Aabb b = bunny.bounds();
    const Vec3d c(b.center());
    const double radius = 1.5 * length(Vec3d(b.extent()));
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (const int sub : {2, 5, 16, 17, 19, 33, 64, 70, 130}) {
        RayBatch rays;
        Vec3d o, target;
        for (int k = 0; k < 400; ++k) {
            // Runs of 8 neighbouring beams (one walk), as a scanner's consecutive pulses.
            if (k % 8 == 0) {
                o = c + normalize(Vec3d{uni(rng), uni(rng), uni(rng)}) * radius;
                target = c + Vec3d{uni(rng), uni(rng), uni(rng)} * (0.3 * radius);
            }
            target += Vec3d{uni(rng), uni(rng), uni(rng)} * (0.01 * radius);
            const double half_angle = std::pow(10.0, -5.0 + 4.6 * (0.5 + 0.5 * uni(rng)));
            push_beam(rays, o, normalize(target - o), sub, half_angle);
            if (k % 5 == 0) {  // origins spread over a few millimetres
                for (int j = 0; j < sub; ++j) {
                    const std::size_t i = rays.size() - 1 - static_cast<std::size_t>(j);
                    rays.ox[i] += 1e-3 * uni(rng);
                    rays.oy[i] += 1e-3 * uni(rng);
                }
            }
        }
        rays.push_back(c + Vec3d{0, 0, radius}, {0, 0, -1});  // a last beam of one ray
        const HitBatch h = expect_beams_match(bunny, rays, static_cast<std::size_t>(sub),
                                              "random " + std::to_string(sub));
        EXPECT_GT(hit_count(h), rays.size() / 10);
    }
}

TEST(PacketBeams, BeamsOfInfiniteAndFiniteInverseDirectionsMatchSingleRays) {
    // Beams over a grid whose sub-rays' x components are tiny of either sign (their inverses
    // overflow to +inf and -inf: still lanes), of both and finite ones in one beam (the x axis
    // then neither still nor of one sign: the finite lanes lie between the infinite bounds),
    // and of both alone (all still). A walk's beams share their origins' x, near a vertex
    // line: the moving lanes leave its slab, within acos(0.97) of the first sub-ray (one
    // frustum).
    const TriangleMesh grid = test::make_grid(64);
    for (const bool finite : {true, false}) {
        RayBatch rays;
        for (int i = 2; i < 62; i += 3) {
            for (int j = 0; j < 60; ++j) {
                const Vec3d o{i + 0.95, j + 0.5, 10.0};
                for (int s = 0; s < 19; ++s) {
                    const double tiny = (s % 2 == 0 ? 1e-40 : -1e-40) * (1 + s % 4);
                    const double x = s % 3 != 2 || !finite ? tiny : 0.02 * (s - 9);
                    rays.push_back(o, Vec3d{x, 0.01 * (s % 5 - 2), -1.0});
                }
            }
        }
        const HitBatch h =
            expect_beams_match(grid, rays, 19, finite ? "infinite and finite x" : "infinite x");
        EXPECT_EQ(hit_count(h), rays.size()) << "rays through a grid below them escaped";
    }
}

TEST(PacketBeams, LastSubRaysOfAnotherAxisOrderMatchSingleRays) {
    // Beams of 19 over the terrain down at just under 45 degrees from z (one frustum), every 13th
    // (the last of a walk of 13 beams) nearer 45 degrees, its cone so wide that three of its outer
    // ring's sub-rays (15 to 17: the walk's last rays, past its last whole packet of AVX2 and
    // AVX-512 alike) move more along x than z: another watertight axis order, so the walk is
    // traced beam by beam.
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh terrain = load_mesh(path);
    const Aabb b = terrain.bounds();
    const Vec3d lo(b.lo), span(b.extent());
    RayBatch rays;
    const double cone = 0.01;
    for (int k = 0; k < 13 * 60; ++k) {
        const double theta = 0.25 * 3.141592653589793 - (k % 13 == 12 ? 0.7 : 3.0) * cone;
        const double f = (k % 60) / 60.0, g = (k / 60) / 13.0;
        const Vec3d o{lo.x + 0.5 * f * span.x, lo.y + g * span.y, lo.z + 0.3 * span.z};
        push_beam(rays, o, Vec3d{std::sin(theta), 0.0, -std::cos(theta)}, 19, cone);
    }
    const auto x_major = [&](std::size_t i) {
        return std::fabs(rays.dx[i]) > std::fabs(rays.dz[i]);
    };
    for (std::size_t s = 0; s < 19; ++s) {
        EXPECT_EQ(x_major(12 * 19 + s), s >= 15 && s <= 17) << "sub-ray " << s;
        EXPECT_FALSE(x_major(s)) << "sub-ray " << s;
    }
    const HitBatch h = expect_beams_match(terrain, rays, 19, "axis order in the last rays");
    EXPECT_GT(hit_count(h), rays.size() / 2);
}

}  // namespace
}  // namespace beamtrace
