// Every backend against brute force on the same rays: real meshes, random and adversarial rays.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <random>
#include <string>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/geometry/moller_trumbore.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// Rays from a sphere around the mesh aimed at random points of its bounding box (most hit),
/// plus 10 % in random directions (many miss).
RayBatch random_rays(const TriangleMesh& mesh, std::size_t n, unsigned seed) {
    return test::rays_toward(mesh.bounds(), n, seed, 10);
}

enum class Aim : std::uint8_t { vertex, edge };

/// Rays aimed exactly at vertices and edge points, with what each one aims at.
struct AimedRays {
    RayBatch rays;
    std::vector<Aim> aim;
    std::vector<std::uint32_t> face;   ///< the face whose vertex or edge ray i aims at
    std::vector<std::uint8_t> corner;  ///< its vertex `corner`, or the edge from it to the next
    std::vector<Vec3d> target;         ///< the point aimed at
    std::size_t vertex_rays = 0, edge_rays = 0;
};

/// Corner k of face f.
Vec3d corner_of(const TriangleMesh& mesh, std::uint32_t f, std::size_t k) {
    return Vec3d(mesh.vertices[mesh.faces[f][k % 3]]);
}

/// Rays from a sphere around the mesh, one per `faces / max_rays`-th face, aimed in turn at a
/// vertex and at a point of an edge of that face (every corner and edge in turn).
AimedRays vertex_and_edge_rays(const TriangleMesh& mesh, std::size_t max_rays, unsigned seed) {
    const Aabb b = mesh.bounds();
    const Vec3d c(b.center());
    const double radius = 1.5 * length(Vec3d(b.extent()));
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    // Edge points from 10 % to 90 % of the way along the edge: strictly between its vertices.
    std::uniform_real_distribution<double> along(0.1, 0.9);
    AimedRays out;
    const std::size_t step = std::max<std::size_t>(1, mesh.faces.size() / max_rays);
    for (std::size_t f = 0; f < mesh.faces.size() && out.rays.size() < max_rays; f += step) {
        const auto face = static_cast<std::uint32_t>(f);
        const std::size_t i = out.rays.size();
        // Alternate by the ray's index, not by f: the step through the faces may be even.
        const Aim aim = i % 2 == 0 ? Aim::vertex : Aim::edge;
        std::size_t k = (i / 2) % 3;
        if (aim == Aim::edge && corner_of(mesh, face, k) == corner_of(mesh, face, k + 1)) {
            k = (k + 1) % 3;  // a degenerate face's zero-length edge has no inner point
        }
        const Vec3d p = corner_of(mesh, face, k), q = corner_of(mesh, face, k + 1);
        const Vec3d target = aim == Aim::vertex ? p : p + (q - p) * along(rng);
        const Vec3d o = c + normalize(Vec3d{g(rng), g(rng), g(rng)}) * radius;
        out.rays.push_back(o, normalize(target - o));
        out.aim.push_back(aim);
        out.face.push_back(face);
        out.corner.push_back(static_cast<std::uint8_t>(k));
        out.target.push_back(target);
        ++(aim == Aim::vertex ? out.vertex_rays : out.edge_rays);
    }
    return out;
}

/// Checks what vertex_and_edge_rays says it made: about half vertex rays and half edge rays,
/// each ray through its target, each vertex target a vertex of its face and each edge target on
/// an edge of its face, strictly between the edge's two vertices (10 % to 90 % of the way).
void expect_real_targets(const TriangleMesh& mesh, const AimedRays& a, const char* what) {
    const std::size_t n = a.rays.size();
    const auto vertex =
        static_cast<std::size_t>(std::count(a.aim.begin(), a.aim.end(), Aim::vertex));
    EXPECT_EQ(a.vertex_rays, vertex) << what;
    EXPECT_EQ(a.edge_rays, n - vertex) << what;
    EXPECT_LE(std::max(a.vertex_rays, a.edge_rays) - std::min(a.vertex_rays, a.edge_rays), 1u)
        << what << ": " << a.vertex_rays << " vertex rays, " << a.edge_rays << " edge rays";
    std::size_t off_ray = 0, at_vertex = 0, inside_edge = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3d o = a.rays.origin(i), d = a.rays.direction(i), x = a.target[i];
        const double s = dot(x - o, d);
        off_ray += length(o + d * s - x) <= 1e-9 * s ? 0 : 1;
        const Vec3d p = corner_of(mesh, a.face[i], a.corner[i]);
        const Vec3d q = corner_of(mesh, a.face[i], a.corner[i] + 1u);
        if (a.aim[i] == Aim::vertex) {
            at_vertex += x == p ? 1 : 0;
            continue;
        }
        // Where x projects onto the edge's line (0 at p, 1 at q), and how far it is off it.
        const double len = length(q - p);
        const double w = dot(x - p, q - p) / (len * len);
        const bool on_line = length(p + (q - p) * w - x) <= 1e-12 * len;
        inside_edge += on_line && w >= 0.1 - 1e-12 && w <= 0.9 + 1e-12 ? 1 : 0;
    }
    EXPECT_EQ(off_ray, 0u) << what << ": rays that miss their target";
    EXPECT_EQ(at_vertex, a.vertex_rays) << what << ": vertex rays aimed at a vertex";
    EXPECT_EQ(inside_edge, a.edge_rays) << what << ": edge rays aimed strictly inside an edge";
}

/// How many rays of each aim meet the mesh first at their target (the oracle's range is the
/// target's distance): the others end on a nearer surface and probe no vertex or edge.
void expect_targets_reached(const AimedRays& a, const HitBatch& oracle, const char* what) {
    std::size_t vertex = 0, edge = 0;
    for (std::size_t i = 0; i < a.rays.size(); ++i) {
        const double range = length(a.target[i] - a.rays.origin(i));
        if (oracle.hit(i) && std::abs(double(oracle.t[i]) - range) <= 1e-6 * range) {
            ++(a.aim[i] == Aim::vertex ? vertex : edge);
        }
    }
    std::printf("  %s: %zu of %zu vertex rays and %zu of %zu edge rays reach their target\n", what,
                vertex, a.vertex_rays, edge, a.edge_rays);
    EXPECT_GE(vertex, a.vertex_rays / 4) << what;
    EXPECT_GE(edge, a.edge_rays / 4) << what;
}

struct NamedBackend {
    BackendKind kind;
    BackendConfig config;
    const char* name;
};

/// Every accelerated backend and build rule set.
std::vector<NamedBackend> accelerated_backends() {
    BackendConfig report;
    report.kdtree = KdTreeBuildConfig::report();
    std::vector<NamedBackend> all;
    for (const BackendKind kind : test::backends(false)) {
        all.push_back({kind, {}, backend_entry(kind).name.data()});
        if (kind == BackendKind::kdtree) {
            all.push_back({kind, report, "kdtree-report-rules"});
        }
        if (kind == BackendKind::bvh) {
            // Every ray through the packet kernels this CPU has, and the single-ray walk.
            for (const int lanes : {8, 16}) {
                BackendConfig packets;
                packets.bvh_trace = {BvhPackets::always, lanes};
                if (bvh_packet_lanes(packets.bvh_trace) == lanes) {
                    all.push_back({kind, packets, lanes == 8 ? "bvh-packets-8" : "bvh-packets-16"});
                }
            }
            BackendConfig single;
            single.bvh_trace.packets = BvhPackets::off;
            all.push_back({kind, single, "bvh-single-rays"});
        }
    }
    return all;
}

/// Barycentric weights (corner 0, 1, 2) of hit i.
std::array<double, 3> weights(const HitBatch& h, std::size_t i) {
    return {1.0 - double(h.u[i]) - double(h.v[i]), double(h.u[i]), double(h.v[i])};
}

/// Slack in barycentrics for "on an edge or vertex": the float ray moves the hit point by ~1e-7
/// of the range, up to ~1e-4 of the smallest triangles' size on these meshes; a random point of
/// a triangle is this near one of its edges with probability ~0.6 %.
constexpr double kFeatureSlack = 1e-3;

/// True when range b is range a within 1e-6 relative (a few float ulps).
bool same_range(float a, float b) {
    return std::abs(double(a) - double(b)) <= 1e-6 * double(a);
}

/// True when the hit of `h` (face h.face[i]) lies on a vertex or edge it shares with face
/// `other` (by position: loaders may duplicate vertices): every corner of its face that is not
/// a corner of `other` has weight at most kFeatureSlack.
bool on_shared_feature(const TriangleMesh& mesh, const HitBatch& h, std::size_t i,
                       std::uint32_t other) {
    const Face& f = mesh.faces[h.face[i]];
    const Face& g = mesh.faces[other];
    const auto w = weights(h, i);
    bool shares = false;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3f& p = mesh.vertices[f[k]];
        const bool shared =
            std::any_of(g.begin(), g.end(), [&](std::uint32_t j) { return mesh.vertices[j] == p; });
        shares = shares || shared;
        if (!shared && w[k] > kFeatureSlack) {
            return false;
        }
    }
    return shares;
}

/// True when the point at range t along ray i lies on face `face` (within float rounding): a
/// legitimate hit of a ray that grazes an edge or vertex, which a non-watertight test may report
/// although the watertight test gives the ray to a neighbour.
bool on_face(const TriangleMesh& mesh, std::uint32_t face, const RayBatch& rays, std::size_t i,
             double t) {
    const Face& f = mesh.faces[face];
    const Vec3d a(mesh.vertices[f[0]]), b(mesh.vertices[f[1]]), c(mesh.vertices[f[2]]);
    const Vec3d q = rays.origin(i) + rays.direction(i) * t;
    const Vec3d n = cross(b - a, c - a);
    const double nn = dot(n, n);
    const double tol = 1e-5 * std::max(1.0, t);
    if (std::abs(dot(q - a, n)) > tol * std::sqrt(nn)) {
        return false;
    }
    const double u = dot(cross(q - a, c - a), n) / nn;
    const double v = dot(cross(b - a, q - a), n) / nn;
    return u >= -kFeatureSlack && v >= -kFeatureSlack && u + v <= 1.0 + kFeatureSlack;
}

/// Our backends share one watertight test and agree exactly with brute force. Embree's
/// triangle test is not that test: on rays aimed exactly at vertices and edges it may give a
/// grazing hit on a neighbouring face (a point of that face within float rounding, nearer than
/// the oracle's) or let a ray slip through an edge, which are counted and limited separately.
bool shares_watertight_test(BackendKind kind) {
    return kind != BackendKind::embree;
}

/// How far a backend's hit on the oracle's face is from the oracle's: the range difference and
/// the distance between the points their barycentrics give, over the range, times cos of the
/// incidence angle. Float rounding in any ray/plane test moves a hit along the ray by a few ulps
/// of the range over that cosine (a grazing ray meets the plane at an ill-conditioned point),
/// so these scaled differences are a few float epsilons (6e-8) whatever the angle.
struct SameFaceError {
    double dt = 0.0, dp = 0.0;
};

SameFaceError same_face_error(const TriangleMesh& mesh, const RayBatch& rays, std::size_t i,
                              const HitBatch& oracle, const HitBatch& got) {
    const Face& f = mesh.faces[oracle.face[i]];
    const Vec3d a(mesh.vertices[f[0]]), b(mesh.vertices[f[1]]), c(mesh.vertices[f[2]]);
    const Vec3d n = cross(b - a, c - a);
    const double cos_incidence = std::abs(dot(n, rays.direction(i))) / length(n);
    const double t = double(oracle.t[i]);
    const double du = double(got.u[i]) - double(oracle.u[i]);
    const double dv = double(got.v[i]) - double(oracle.v[i]);
    return {std::abs(double(got.t[i]) - t) * cos_incidence / t,
            length((b - a) * du + (c - a) * dv) * cos_incidence / t};
}

/// Limit on both SameFaceError figures. Our backends run the same watertight arithmetic on the
/// same float ray as brute force, so their t, u and v must be identical (checked bit for bit).
/// Embree solves for them its own way in float: measured at most 4.2e-7 here (7 float
/// epsilons); 2e-6 leaves a margin of 5. (Unscaled, its barycentrics differ by up to 2e-3 and its
/// ranges by 9e-6 relative on rays at 0.2 degrees from the surface.)
constexpr double kEmbreeSameFaceLimit = 2e-6;

bool same_hit(const HitBatch& oracle, const HitBatch& got, std::size_t i, BackendKind kind,
              const SameFaceError& e) {
    if (shares_watertight_test(kind)) {
        return got.t[i] == oracle.t[i] && got.u[i] == oracle.u[i] && got.v[i] == oracle.v[i];
    }
    return e.dt <= kEmbreeSameFaceLimit && e.dp <= kEmbreeSameFaceLimit;
}

/// How a backend's hit of one ray compares with brute force's.
enum class Verdict : std::uint8_t {
    agree,    ///< both miss, or the same face at the same range and barycentrics (see same_hit)
    tie,      ///< another face at the same range, through an edge or vertex both faces share
    grazing,  ///< (Embree) a nearer point of a face that the watertight test misses by rounding
    slipped,  ///< (Embree) missed or farther, the oracle's hit on an edge or vertex
    off,      ///< same face, but range or barycentrics out of tolerance
    wrong,    ///< anything else
};
constexpr std::size_t kVerdicts = 6;

Verdict classify(const TriangleMesh& mesh, const RayBatch& rays, std::size_t i,
                 const HitBatch& oracle, const HitBatch& got, BackendKind kind) {
    const bool oh = oracle.hit(i), gh = got.hit(i);
    if (!oh && !gh) {
        return Verdict::agree;
    }
    if (oh && gh && got.face[i] == oracle.face[i]) {
        const SameFaceError e = same_face_error(mesh, rays, i, oracle, got);
        return same_hit(oracle, got, i, kind, e) ? Verdict::agree : Verdict::off;
    }
    // Both faces hold the point where the ray meets their shared edge or vertex, at one range:
    // either is a right nearest hit (the Backend contract gives it to the lower face ID, which our
    // backends must do exactly).
    if (oh && gh && same_range(oracle.t[i], got.t[i]) &&
        on_shared_feature(mesh, oracle, i, got.face[i]) &&
        on_shared_feature(mesh, got, i, oracle.face[i])) {
        return Verdict::tie;
    }
    if (shares_watertight_test(kind)) {
        return Verdict::wrong;
    }
    if (gh && (!oh || got.t[i] < oracle.t[i]) &&
        on_face(mesh, got.face[i], rays, i, double(got.t[i]))) {
        return Verdict::grazing;
    }
    const auto w = weights(oracle, i);
    if (oh && (!gh || got.t[i] > oracle.t[i]) && std::min({w[0], w[1], w[2]}) < kFeatureSlack) {
        return Verdict::slipped;
    }
    return Verdict::wrong;
}

/// Verdicts of one backend on a batch, and the largest same-face deviations from brute force.
struct Tally {
    std::array<std::size_t, kVerdicts> count{};
    SameFaceError max;  ///< the largest of each on same-face hits
    [[nodiscard]] std::size_t operator[](Verdict v) const {
        return count[static_cast<std::size_t>(v)];
    }
};

Tally tally(const TriangleMesh& mesh, const RayBatch& rays, const HitBatch& oracle,
            const HitBatch& got, BackendKind kind, const std::string& label) {
    Tally t;
    std::size_t reported = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Verdict v = classify(mesh, rays, i, oracle, got, kind);
        ++t.count[static_cast<std::size_t>(v)];
        if (oracle.hit(i) && got.face[i] == oracle.face[i]) {
            const SameFaceError e = same_face_error(mesh, rays, i, oracle, got);
            t.max.dt = std::max(t.max.dt, e.dt);
            t.max.dp = std::max(t.max.dp, e.dp);
        }
        const bool bad = v == Verdict::off || v == Verdict::wrong;
        if (bad && shares_watertight_test(kind) && ++reported <= 3) {
            ADD_FAILURE() << label << " ray " << i << ": face " << got.face[i] << " t " << got.t[i]
                          << " u " << got.u[i] << " v " << got.v[i] << " vs brute face "
                          << oracle.face[i] << " t " << oracle.t[i] << " u " << oracle.u[i] << " v "
                          << oracle.v[i];
        }
    }
    return t;
}

/// The limits on a tally. Our backends: every ray agrees but for a few ties (above). Embree: on
/// random rays, only a very few ties; on rays aimed at vertices and edges, any number of ties (its
/// test need not give a shared edge to the lower face), a few grazing or slipping rays, and a
/// very few rays that graze at a wider angle than on_face's tolerance.
void expect_within_limits(const Tally& t, std::size_t n, BackendKind kind, bool edge_rays,
                          const std::string& label) {
    const std::size_t bad = t[Verdict::off] + t[Verdict::wrong];
    const std::size_t allowances = t[Verdict::grazing] + t[Verdict::slipped];
    std::printf(
        "  %s: %zu rays, %zu agree, %zu ties, %zu grazing, %zu slipped, %zu off, %zu wrong; "
        "same face, times cos/t: max |dt| %.1e, max |dp| %.1e\n",
        label.c_str(), n, t[Verdict::agree], t[Verdict::tie], t[Verdict::grazing],
        t[Verdict::slipped], t[Verdict::off], t[Verdict::wrong], t.max.dt, t.max.dp);
    if (shares_watertight_test(kind)) {
        EXPECT_EQ(bad + allowances, 0u) << label;
        // Not even a tie: our traversals pick the nearest divided range, then the lowest face,
        // whatever order they visit faces in (NearestVisitor, slab_interval), as brute force.
        EXPECT_EQ(t[Verdict::tie], 0u) << label;
        return;
    }
    if (!edge_rays) {
        EXPECT_EQ(bad + allowances, 0u) << label;
        EXPECT_LE(t[Verdict::tie], n / 1000) << label;
        return;
    }
    EXPECT_LE(bad, std::max<std::size_t>(3, n / 1000)) << label;
    EXPECT_LE(allowances, n / 50) << label;
}

/// Every accelerated backend against brute force on `rays`; returns brute force's hits.
/// `edge_rays`: rays aimed exactly at vertices and edges, where Embree may differ (see above).
HitBatch expect_agreement(const TriangleMesh& mesh, const RayBatch& rays, const char* what,
                          bool edge_rays = false) {
    ThreadPool pool(0);
    const auto brute = make_backend(BackendKind::brute, mesh, pool);
    HitBatch oracle = brute->intersect(rays, pool);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += oracle.hit(i) ? 1 : 0;
    }
    EXPECT_GT(hits, rays.size() / 10) << what << ": the test rays should hit something";
    for (const auto& [kind, config, name] : accelerated_backends()) {
        const auto backend = make_backend(kind, mesh, pool, config);
        const HitBatch got = backend->intersect(rays, pool);
        const std::string label = std::string(what) + " " + name;
        expect_within_limits(tally(mesh, rays, oracle, got, kind, label), rays.size(), kind,
                             edge_rays, label);
        // Occlusion agrees with the nearest-hit query.
        std::vector<std::uint8_t> occ;
        backend->occluded(rays, 0, rays.size(), occ, pool);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            differ += (occ[i] != 0) == got.hit(i) ? 0 : 1;
        }
        EXPECT_EQ(differ, 0u) << label << ": rays whose occlusion differs from the nearest hit";
    }
    return oracle;
}

TEST(CrossCheck, BunnyRandomRays) {
    const auto path = test::shared_data("meshes/small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    expect_agreement(mesh, random_rays(mesh, test::heavy_scale(20000), 1), "bunny");
}

TEST(CrossCheck, TerrainRandomRays) {
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    expect_agreement(mesh, random_rays(mesh, test::heavy_scale(30000), 2), "terrain");
}

/// Rays aimed at vertices and edges (checked to be that) against brute force.
void expect_vertex_and_edge_agreement(const TriangleMesh& mesh, unsigned seed, const char* what) {
    const AimedRays aimed = vertex_and_edge_rays(mesh, test::heavy_scale(10000), seed);
    expect_real_targets(mesh, aimed, what);
    expect_targets_reached(aimed, expect_agreement(mesh, aimed.rays, what, true), what);
}

TEST(CrossCheck, BunnyVertexAndEdgeRays) {
    const auto path = test::shared_data("meshes/small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    expect_vertex_and_edge_agreement(mesh, 3, "bunny-vertices");
}

TEST(CrossCheck, TerrainVertexAndEdgeRays) {
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    expect_vertex_and_edge_agreement(mesh, 4, "terrain-vertices");
}

/// Rays from inside a closed mesh through its vertices and edges must hit: no leaks.
void expect_no_leaks(const TriangleMesh& mesh, const Vec3d& inside, const char* what) {
    RayBatch rays;
    for (const auto& v : mesh.vertices) {
        rays.push_back(inside, normalize(Vec3d(v) - inside));
    }
    for (const auto& f : mesh.faces) {
        for (int k = 0; k < 3; ++k) {
            const Vec3d a(mesh.vertices[f[static_cast<std::size_t>(k)]]);
            const Vec3d b(mesh.vertices[f[static_cast<std::size_t>((k + 1) % 3)]]);
            rays.push_back(inside, normalize((a + b) * 0.5 - inside));
        }
    }
    ThreadPool pool(0);
    auto backends = accelerated_backends();
    backends.push_back({BackendKind::brute, {}, "brute"});
    for (const auto& [kind, config, name] : backends) {
        const auto backend = make_backend(kind, mesh, pool, config);
        const HitBatch hits = backend->intersect(rays, pool);
        std::size_t leaks = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            leaks += hits.hit(i) ? 0 : 1;
        }
        EXPECT_EQ(leaks, 0u) << what << " " << name << ": " << leaks << " of " << rays.size()
                             << " rays escaped";
    }
}

TEST(CrossCheck, NoLeaksThroughIcosphereVerticesAndEdges) {
    expect_no_leaks(test::make_icosphere(4, 3.0f), {0.0, 0.0, 0.0}, "icosphere");
    expect_no_leaks(test::make_icosphere(3, 1.0f), {0.1, -0.2, 0.05}, "icosphere-offset");
}

TEST(CrossCheck, NoLeaksThroughSpotVerticesAndEdges) {
    const auto path = test::shared_data("meshes/small/spot.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    // An interior point: halfway between the first two hits of a ray through the body.
    ThreadPool pool(1);
    const auto bvh = make_backend(BackendKind::bvh, mesh, pool);
    RayBatch probe;
    const Vec3d c(mesh.bounds().center());
    probe.push_back(c + Vec3d{0, 0, 10}, {0, 0, -1});
    AllHits all;
    bvh->intersect_all(probe, Facing::both, all, pool);
    ASSERT_GE(all.count(0), 2u);
    ASSERT_TRUE(all.front[0]);
    const double mid = 0.5 * (double(all.t[0]) + double(all.t[1]));
    expect_no_leaks(mesh, c + Vec3d{0, 0, 10} + Vec3d{0, 0, -1} * mid, "spot");
}

TEST(CrossCheck, AxisAlignedRaysThroughGridVerticesAndEdges) {
    // Exactly representable vertices and rays exactly through them: the hardest case for
    // slab tests (origin on box planes, zero direction components) and for the k-d tree (split
    // planes through the ray).
    const TriangleMesh grid = test::make_grid(32);
    RayBatch rays;
    for (int j = 0; j <= 64; ++j) {
        for (int i = 0; i <= 64; ++i) {
            const double x = 0.5 * i, y = 0.5 * j;
            rays.push_back({x, y, 10.0}, {0, 0, -1});
            rays.push_back({x, y, -10.0}, {0, 0, 1});
        }
    }
    ThreadPool pool(2);
    auto backends = accelerated_backends();
    backends.push_back({BackendKind::brute, {}, "brute"});
    for (const auto& [kind, config, name] : backends) {
        const auto backend = make_backend(kind, grid, pool, config);
        const HitBatch hits = backend->intersect(rays, pool);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const double x = rays.ox[i], y = rays.oy[i];
            if (!shares_watertight_test(kind) && (x == 32.0 || y == 32.0 || x == 0.0 || y == 0.0)) {
                // Embree's edge test is not closed on every side: rays exactly along the outer
                // boundary of an open mesh may miss it (a ray off the mesh by any amount does).
                continue;
            }
            ASSERT_TRUE(hits.hit(i)) << name << " ray " << i << " leaked";
            if (shares_watertight_test(kind)) {
                EXPECT_EQ(hits.t[i], 10.0f) << name << " ray " << i;
            } else {
                // Embree's AVX2 kernels divide by a refined reciprocal: 10 within an ulp or two
                // on an AVX2-only CPU (AMD Zen 3), exactly 10 on an AVX-512 one.
                EXPECT_NEAR(hits.t[i], 10.0f, 4e-6f) << name << " ray " << i;
            }
        }
    }
    // Embree against brute force on the interior rays only (see above).
    RayBatch interior;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const double x = rays.ox[i], y = rays.oy[i];
        if (x > 0.0 && x < 32.0 && y > 0.0 && y < 32.0) {
            interior.push_back(rays.origin(i), rays.direction(i));
        }
    }
    expect_agreement(grid, interior, "grid", true);
}

TEST(CrossCheck, AllHitsMatchBruteForceAndMollerTrumbore) {
    const TriangleMesh sphere = test::make_icosphere(3, 2.0f);
    ThreadPool pool(2);
    RayBatch rays;
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const Vec3d o = normalize(Vec3d{g(rng), g(rng), g(rng)}) * 5.0;
        rays.push_back(o, normalize(Vec3d{g(rng), g(rng), g(rng)} * 0.8 - o));
    }
    AllHits ref;
    make_backend(BackendKind::brute, sphere, pool)->intersect_all(rays, Facing::both, ref, pool);
    const std::vector<BackendKind> kinds = test::backends(false);
    for (BackendKind kind : kinds) {
        for (Facing facing : {Facing::front, Facing::back, Facing::both}) {
            AllHits got;
            make_backend(kind, sphere, pool)->intersect_all(rays, facing, got, pool);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                std::vector<std::uint32_t> expect;
                for (std::size_t k = ref.offsets[i]; k < ref.offsets[i + 1]; ++k) {
                    const bool front = ref.front[k] != 0;
                    if (facing == Facing::both || (facing == Facing::front) == front) {
                        expect.push_back(ref.face[k]);
                    }
                }
                std::vector<std::uint32_t> faces(
                    got.face.begin() + static_cast<long>(got.offsets[i]),
                    got.face.begin() + static_cast<long>(got.offsets[i + 1]));
                ASSERT_EQ(faces, expect) << to_string(kind) << " ray " << i;
                if (facing == Facing::both) {
                    const auto mt =
                        ray_intersect_all(sphere, rays.origin(i), rays.direction(i), Facing::both);
                    EXPECT_EQ(mt.size(), faces.size()) << "ray " << i;
                }
            }
        }
    }
}

TEST(CrossCheck, ResultsDoNotDependOnThreadCount) {
    const TriangleMesh sphere = test::make_icosphere(3, 2.0f);
    RayBatch rays;
    std::mt19937 rng(9);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < 20000; ++i) {
        const Vec3d o = normalize(Vec3d{g(rng), g(rng), g(rng)}) * 5.0;
        rays.push_back(o, normalize(Vec3d{g(rng), g(rng), g(rng)} - o));
    }
    ThreadPool one(1), four(4);
    const std::vector<BackendKind> kinds = test::backends(false);
    for (BackendKind kind : kinds) {
        const HitBatch a = make_backend(kind, sphere, one)->intersect(rays, one);
        const HitBatch b = make_backend(kind, sphere, four)->intersect(rays, four);
        EXPECT_EQ(a.t, b.t);
        EXPECT_EQ(a.face, b.face);
        EXPECT_EQ(a.u, b.u);
    }
}

}  // namespace
}  // namespace beamtrace
