// End-to-end runs of the beamtrace CLI and of the documented examples.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/io/hits_csv.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

test::RunResult run(const std::string& args, const std::string& env = "") {
    return test::run_command(env + " " + std::string(BEAMTRACE_CLI_PATH) + " " + args);
}

std::size_t count_lines(const std::string& s) {
    return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

TEST(Cli, DemoScanWritesAllOutputsConsistently) {
    test::TempDir dir;
    const auto r = run("scan --demo --outputs ply,npy,png,csv --output " + dir.path().string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const ImageSensorConfig cam = demo_sensor();
    const auto n = static_cast<std::size_t>(cam.width * cam.height);
    const HitsCsv hits = read_hits_csv(dir / "hits.csv");
    ASSERT_EQ(hits.size(), n);
    const auto points = read_points_ply(dir / "points.ply");
    std::size_t n_hits = 0;
    for (std::size_t i = 0; i < n; ++i) {
        EXPECT_EQ(hits.ray[i], i);
        n_hits += hits.face_id[i] >= 0 ? 1 : 0;
        if (hits.face_id[i] < 0) {
            EXPECT_TRUE(std::isinf(hits.range_m[i]));
        }
    }
    ASSERT_EQ(points.size(), n_hits);
    // Each point lies at its range along its ray, and carries the face of hits.csv.
    const RayBatch rays = cast_rays_pinhole(cam);
    for (std::size_t k = 0; k < points.size(); k += 97) {
        const auto& p = points[k];
        const std::size_t i = p.ray_index;
        EXPECT_EQ(static_cast<std::int64_t>(p.face_id), hits.face_id[i]);
        // hits.csv prints the float range in its shortest form: equal to ~1e-7 relative.
        EXPECT_NEAR(p.x, rays.ox[i] + hits.range_m[i] * rays.dx[i], 1e-6 * hits.range_m[i]);
        EXPECT_NEAR(p.z, rays.oz[i] + hits.range_m[i] * rays.dz[i], 1e-6 * hits.range_m[i]);
    }
    // The range image is h x w, row-major, pixel (v, u) = ray u * h + v, misses 0.
    const NpyArray img = read_npy_f32(dir / "range.npy");
    ASSERT_EQ(img.shape, (std::vector<std::size_t>{static_cast<std::size_t>(cam.height),
                                                   static_cast<std::size_t>(cam.width)}));
    for (int u = 0; u < cam.width; u += 37) {
        for (int v = 0; v < cam.height; v += 13) {
            const std::size_t i = ray_index(u, v, cam.height);
            const float px = img.data[static_cast<std::size_t>(v * cam.width + u)];
            if (hits.face_id[i] < 0) {
                EXPECT_EQ(px, 0.0f);
            } else {
                EXPECT_FLOAT_EQ(px, static_cast<float>(hits.range_m[i]));
            }
        }
    }
    EXPECT_TRUE(std::filesystem::file_size(dir / "range.png") > 1000);
}

TEST(Cli, OutputsAreIdenticalForAnyThreadCountAndBackend) {
    test::TempDir dir;
    const std::string common =
        "scan --demo --quiet --width 96 --height 48 --outputs ply,npy,png,csv ";
    // The default backend (Embree where built) at 1 and 3 threads; our own backends, which
    // agree bit for bit (ties to the lowest face ID), at their defaults.
    ASSERT_EQ(run(common + "--threads 1 --output " + (dir / "t1").string()).exit_code, 0);
    ASSERT_EQ(run(common + "--threads 3 --output " + (dir / "t3").string()).exit_code, 0);
    ASSERT_EQ(run(common + "--backend bvh --threads 1 --output " + (dir / "b1").string()).exit_code,
              0);
    ASSERT_EQ(run(common + "--backend bvh --threads 3 --output " + (dir / "b3").string()).exit_code,
              0);
    ASSERT_EQ(run(common + "--backend kdtree --output " + (dir / "kd").string()).exit_code, 0);
    ASSERT_EQ(run(common + "--backend brute --output " + (dir / "bf").string()).exit_code, 0);
    ASSERT_EQ(
        run(common + "--backend kdtree --kdtree-rules report --output " + (dir / "kr").string())
            .exit_code,
        0);
    for (const char* f : {"hits.csv", "points.ply", "range.npy", "range.png"}) {
        const std::string def = test::read_file(dir / "t1" / f);
        EXPECT_FALSE(def.empty());
        EXPECT_EQ(def, test::read_file(dir / "t3" / f)) << f;
        const std::string ref = test::read_file(dir / "b1" / f);
        EXPECT_FALSE(ref.empty());
        EXPECT_EQ(ref, test::read_file(dir / "b3" / f)) << f;
        if (std::string(f) != "points.ply") {  // the PLY comment names the backend
            EXPECT_EQ(ref, test::read_file(dir / "kd" / f)) << f;
            EXPECT_EQ(ref, test::read_file(dir / "bf" / f)) << f;
            EXPECT_EQ(ref, test::read_file(dir / "kr" / f)) << f;
        }
    }
    // Embree (the default where built) finds the same faces at ranges within float rounding.
    const HitsCsv a = read_hits_csv(dir / "t1" / "hits.csv");
    const HitsCsv b = read_hits_csv(dir / "b1" / "hits.csv");
    ASSERT_EQ(a.face_id.size(), b.face_id.size());
    std::size_t other_face = 0;
    for (std::size_t i = 0; i < a.face_id.size(); ++i) {
        ASSERT_EQ(a.face_id[i] < 0, b.face_id[i] < 0) << "ray " << i;
        other_face += a.face_id[i] != b.face_id[i] ? 1 : 0;
        if (b.face_id[i] >= 0) {
            EXPECT_NEAR(a.range_m[i], b.range_m[i], 1e-4 * b.range_m[i]) << "ray " << i;
        }
    }
    EXPECT_LE(other_face, 2u);  // rays aimed exactly at a shared edge
}

TEST(Cli, BenchMeasuresTheLimitBackendsAndSurveysOnTheSameRays) {
    const std::string survey = std::string(BEAMTRACE_EXAMPLES_DIR) + "/surveys/car_hdl64.yaml";
    test::TempDir dir;
    const auto r = run("bench " + survey +
                       " --pulses 20000 --repeats 1 --min-time 0 --threads 1 2 --quiet --output " +
                       (dir / "report.md").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(test::read_file(dir / "report.md"), r.out);
    // The CLI is single-threaded when the bench starts: each memory run is a child of its own.
    EXPECT_NE(r.out.find("Peak RSS: each end-to-end run in a child process of its own"),
              std::string::npos)
        << r.out;
    // "### car_hdl64: 80182 triangles, 20000 pulses, 20000 rays, H hits, H points"
    const auto head = r.out.find("### car_hdl64: ");
    ASSERT_NE(head, std::string::npos) << r.out;
    unsigned long long triangles = 0, pulses = 0, rays = 0, hits = 0, points = 0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + head,
                          "### car_hdl64: %llu triangles, %llu pulses, %llu rays, %llu hits, "
                          "%llu points",
                          &triangles, &pulses, &rays, &hits, &points),
              5)
        << r.out;
    EXPECT_EQ(triangles, make_demo_scene().triangle_count());
    EXPECT_EQ(pulses, 20000u);
    EXPECT_EQ(rays, 20000u);
    EXPECT_GT(hits, 15000u);
    EXPECT_EQ(points, hits);
    for (const char* row :
         {"| 1 | our bvh | ", "| 2 | our bvh | ", "| 1 | **survey end to end** (LAS written) | ",
          "| 2 | **survey end to end** (LAS written) | ", "Scaling 1 -> 2"}) {
        EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
    }
    if (test::with_embree()) {
        EXPECT_NE(r.out.find("| 1 | Embree rtcIntersect1 | "), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("| 1 | our embree | "), std::string::npos) << r.out;
    }
    // Bad settings: one line, exit code 2.
    const auto bad = run("bench " + survey + " --threads 0 --quiet");
    EXPECT_EQ(bad.exit_code, 2) << bad.out;
    EXPECT_NE(bad.out.find("threads: 0"), std::string::npos) << bad.out;
    EXPECT_EQ(count_lines(bad.out), 1u) << bad.out;
    // A survey too long to hold its rays: told to use --pulses.
    const std::string big = std::string(BEAMTRACE_EXAMPLES_DIR) + "/surveys/airborne_srtm_1e8.yaml";
    const auto huge = run("bench " + big + " --quiet");
    EXPECT_EQ(huge.exit_code, 2) << huge.out;
    EXPECT_NE(huge.out.find("use --pulses"), std::string::npos) << huge.out;
    // A scene with exact spheres: refused at once (the limit loop is given triangles only).
    const std::string spheres =
        std::string(BEAMTRACE_EXAMPLES_DIR) + "/surveys/tripod_spheres.yaml";
    const auto refused = run("bench " + spheres + " --quiet --output " + (dir / "s.md").string());
    EXPECT_EQ(refused.exit_code, 2) << refused.out;
    EXPECT_NE(refused.out.find("tripod_spheres.yaml: part 'targets' is an exact sphere"),
              std::string::npos)
        << refused.out;
    EXPECT_EQ(count_lines(refused.out), 1u) << refused.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "s.md"));
}

TEST(Cli, BadInputsGiveOneLineErrorExitCode2AndNoOutputs) {
    test::TempDir dir;
    const std::string out = (dir / "out").string();
    std::ofstream(dir / "broken.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
    std::ofstream(dir / "mesh.xyz") << "1 2 3\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"scan --demo --output " + out + " --hfov 4", "hfov"},
        {"scan --demo --output " + out + " --width 0", "width"},
        {"scan --demo --output " + out + " --pattern fisheye", "fisheye"},
        {"scan --demo --output " + out + " --backend embree9", "embree9"},
        {"scan --demo --output " + out + " --kdtree-rules best", "--kdtree-rules"},
        {"scan --demo --output " + out + " --position 1,2", "--position"},
        {"scan --demo --output " + out + " --exclude-faces 5-2", "5-2"},
        {"scan --mesh " + (dir / "nope.obj").string() + " --output " + out, "nope.obj"},
        {"scan --mesh " + (dir / "broken.obj").string() + " --output " + out, "broken.obj:3"},
        {"scan --mesh " + (dir / "mesh.xyz").string() + " --output " + out, "mesh.xyz"},
        {"scan --output " + out, "--demo"},
        {"scan --demo", "--output"},
        {"scan --demo --output " + out + " --frobnicate", "frobnicate"},
        {"scan --demo --output " + out + " --pattern rays", "--rays"},
    };
    for (const auto& [args, needle] : cases) {
        const auto r = run(args);
        EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
        EXPECT_NE(r.out.find(needle), std::string::npos) << args << "\n" << r.out;
        EXPECT_EQ(count_lines(r.out), 1u) << args << "\n" << r.out;
        EXPECT_FALSE(std::filesystem::exists(dir / "out" / "points.ply")) << args;
    }
}

TEST(Cli, ProgressBarAndSummary) {
    test::TempDir dir;
    const auto r = run("scan --demo --progress --output " + dir.path().string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("tracing ["), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("100.0%"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("faces 80180-80181: occluder"), std::string::npos) << r.out;
    const auto q = run("scan --demo --quiet --progress --output " + (dir / "q").string());
    ASSERT_EQ(q.exit_code, 0);
    EXPECT_TRUE(q.out.empty()) << q.out;
}

TEST(Cli, RaysFileWithImageShape) {
    test::TempDir dir;
    {
        std::ofstream f(dir / "rays.csv");
        f << "ox,oy,oz,dx,dy,dz\n";
        for (int i = 0; i < 6; ++i) {
            f << "0," << i << ",50,0,0,-1\n";
        }
    }
    const std::string rays = (dir / "rays.csv").string();
    auto r =
        run("scan --demo --pattern rays --rays " + rays +
            " --width 3 --height 2 --outputs ply,npy,png,csv --output " + (dir / "ok").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const HitsCsv hits = read_hits_csv(dir / "ok" / "hits.csv");
    ASSERT_EQ(hits.size(), 6u);
    for (std::size_t i = 0; i < 6; ++i) {
        const double ground = demo_terrain_height(0.0, static_cast<double>(i));
        // Rays at y = 0..1.75 hit vehicle 1 (top of the turret at about 2.6 m), others the ground.
        EXPECT_GT(hits.range_m[i], 40.0);
        EXPECT_LE(hits.range_m[i], 50.0 - ground + 1e-3);
    }
    EXPECT_EQ(read_npy_f32(dir / "ok" / "range.npy").shape, (std::vector<std::size_t>{2, 3}));
    r = run("scan --demo --pattern rays --rays " + rays + " --width 4 --height 2 --output " +
            (dir / "bad").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.out.find("6 rays"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad" / "points.ply"));
}

TEST(Cli, ScanTakesGltfMeshesAndSaysSo) {
    EXPECT_NE(run("scan --help").out.find("glTF"), std::string::npos);
    // BoxTextured.glb (Khronos sample): the cube [-0.5, 0.5]^3. Rays down from z = 5.
    const auto glb = test::shared_data("meshes/gltf/BoxTextured.glb");
    BEAMTRACE_REQUIRE_FILE(glb);
    test::TempDir dir;
    {
        std::ofstream f(dir / "rays.csv");
        f << "ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n0.4,-0.3,5,0,0,-1\n2,0,5,0,0,-1\n";
    }
    const auto r =
        run("scan --mesh " + glb.string() + " --pattern rays --rays " +
            (dir / "rays.csv").string() + " --outputs csv --output " + (dir / "out").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const HitsCsv hits = read_hits_csv(dir / "out" / "hits.csv");
    ASSERT_EQ(hits.size(), 3u);
    EXPECT_NEAR(hits.range_m[0], 4.5, 1e-5);
    EXPECT_NEAR(hits.range_m[1], 4.5, 1e-5);
    EXPECT_FALSE(std::isfinite(hits.range_m[2]));  // beside the box
}

int run_example(const std::string& name, const std::filesystem::path& out,
                const std::string& args = "") {
    const std::string cmd = "BEAMTRACE=" + std::string(BEAMTRACE_CLI_PATH) +
                            " PUSHBROOM_RAYS=" + std::string(BEAMTRACE_PUSHBROOM_PATH) +
                            " OUT=" + out.string() + " bash " + BEAMTRACE_EXAMPLES_DIR + "/" +
                            name + " --quiet " + args + " > /dev/null 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Examples, Panorama360) {
    test::TempDir dir;
    ASSERT_EQ(run_example("panorama.sh", dir.path()), 0);
    const NpyArray img = read_npy_f32(dir / "range.npy");
    ASSERT_EQ(img.shape, (std::vector<std::size_t>{200, 3600}));
    // A full turn: the first and last columns look the same way (the report's linspace over
    // [pi, -pi] repeats it), so they see the same ranges.
    for (std::size_t v = 0; v < 200; ++v) {
        EXPECT_NEAR(img.data[v * 3600], img.data[v * 3600 + 3599], 1e-3) << v;
    }
    // The lower rows look down at the ground all round.
    for (std::size_t u = 0; u < 3600; u += 10) {
        EXPECT_GT(img.data[199 * 3600 + u], 0.0f) << u;
    }
}

TEST(Examples, OcclusionDropsOnlyTheOccluderPoints) {
    test::TempDir dir;
    ASSERT_EQ(run_example("occlusion.sh", dir.path(), "--outputs ply,csv"), 0);
    const HitsCsv hits = read_hits_csv(dir / "hits.csv");
    const auto points = read_points_ply(dir / "points.ply");
    const Scene scene = make_demo_scene();
    const auto occluder = scene.parts.back();
    ASSERT_EQ(occluder.name, "occluder");
    ASSERT_EQ(occluder.first_face, 80180u);
    std::size_t on_occluder = 0, on_vehicle = 0, n_hits = 0;
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (hits.face_id[i] < 0) {
            continue;
        }
        ++n_hits;
        const auto part = scene.part_of_face(static_cast<std::uint32_t>(hits.face_id[i]));
        on_occluder += part == 4 ? 1 : 0;
        on_vehicle += part == 1 ? 1 : 0;
    }
    EXPECT_GT(on_occluder, 1000u) << "the plane is in view";
    EXPECT_GT(on_vehicle, 1000u) << "the vehicle is in view";
    EXPECT_EQ(points.size(), n_hits - on_occluder);
    for (const auto& p : points) {
        ASSERT_LT(p.face_id, 80180u);
    }
}

TEST(Examples, PushbroomFromRaysFile) {
    test::TempDir dir;
    ASSERT_EQ(run_example("pushbroom.sh", dir.path()), 0);
    const NpyArray img = read_npy_f32(dir / "range.npy");
    ASSERT_EQ(img.shape, (std::vector<std::size_t>{500, 500}));
    // Flying at 200 m over terrain within a few metres of 0: every range is about 200 / cos.
    for (float r : img.data) {
        ASSERT_GT(r, 190.0f);
        ASSERT_LT(r, 220.0f);
    }
}

}  // namespace
}  // namespace beamtrace
