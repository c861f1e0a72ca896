// `beamtrace scan --outputs`: which files a scan writes, and that its parallel writers (records
// encoded by chunk on several threads, each written at its offset) give the bytes of the
// library's serial writers and readers.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/colormap.hpp"
#include "beamtrace/io/hits_csv.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/io/png_reader.hpp"
#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"
#include "beamtrace/pipeline/scan_job.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

test::RunResult run(const std::string& args) {
    return test::run_command(std::string(BEAMTRACE_CLI_PATH) + " " + args);
}

std::set<std::string> names_in(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) {
        names.insert(e.path().filename().string());
    }
    return names;
}

TEST(ScanOutputs, ParsedOnceInTheLibraryWithTheDefaultPlyNpy) {
    EXPECT_EQ(to_string(ScanOutputs{}), "ply,npy");
    EXPECT_EQ(parse_scan_outputs("ply,npy"), ScanOutputs{});
    const ScanOutputs all = parse_scan_outputs("laz,csv,png,npy,ply");
    EXPECT_EQ(to_string(all), "ply,npy,png,csv,laz");  // listed in one order, whatever given
    const ScanOutputs csv = parse_scan_outputs("csv");
    EXPECT_TRUE(csv.csv);
    EXPECT_FALSE(csv.ply || csv.npy || csv.png || csv.laz);
    for (const char* bad : {"", "ply,", ",ply", "ply,,npy", "PLY", "ply,ply", "las", "ply npy"}) {
        EXPECT_THROW((void)parse_scan_outputs(bad), ConfigError) << bad;
    }
    ScanJobConfig c;
    c.demo = true;
    c.output_dir = "x";
    c.outputs = parse_scan_outputs("csv");
    EXPECT_TRUE(c.validate().empty());
    c.outputs.csv = false;  // none at all: only through the library
    ASSERT_EQ(c.validate().size(), 1u);
    EXPECT_NE(c.validate()[0].find("--outputs"), std::string::npos);
}

TEST(ScanOutputs, EachSelectionWritesItsFilesAndNoOther) {
    test::TempDir dir;
    const std::string common = "scan --demo --width 64 --height 32 --quiet --threads 2 ";
    const std::vector<std::pair<std::string, std::set<std::string>>> cases = {
        {"", {"points.ply", "range.npy"}},
        {"--outputs ply", {"points.ply"}},
        {"--outputs npy", {"range.npy"}},
        {"--outputs png", {"range.png"}},
        {"--outputs csv", {"hits.csv"}},
        {"--outputs laz", {"points.laz"}},
        {"--outputs csv,npy", {"hits.csv", "range.npy"}},
        {"--laz", {"points.ply", "range.npy", "points.laz"}},
        {"--outputs csv --laz", {"hits.csv", "points.laz"}},
        {"--outputs ply,npy,png,csv,laz",
         {"points.ply", "range.npy", "range.png", "hits.csv", "points.laz"}},
    };
    int k = 0;
    for (const auto& [args, files] : cases) {
        const fs::path out = dir / std::to_string(k++);
        const auto r = run(common + args + " --output " + out.string());
        ASSERT_EQ(r.exit_code, 0) << args << ": " << r.out;
        EXPECT_EQ(names_in(out), files) << args;
        for (const auto& f : files) {
            EXPECT_GT(fs::file_size(out / f), 0u) << args << " " << f;
        }
    }
    // Without an image grid (a rays file without --width/--height), the images are skipped.
    test::write_file(dir / "rays.csv", "ox,oy,oz,dx,dy,dz\n0,0,50,0,0,-1\n0,1,50,0,0,-1\n");
    const auto r = run("scan --demo --pattern rays --rays " + (dir / "rays.csv").string() +
                       " --quiet --output " + (dir / "rays").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(names_in(dir / "rays"), std::set<std::string>{"points.ply"});
}

TEST(ScanOutputs, BadListsAreOneLineErrorsWithExit2AndWriteNothing) {
    test::TempDir dir;
    const std::string out = (dir / "out").string();
    for (const std::string bad : {"''", "ply,", "ply,,npy", "PLY", "ply,ply", "las", "'ply npy'"}) {
        const auto r = run("scan --demo --quiet --outputs " + bad + " --output " + out);
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << bad << ": " << r.out;
        EXPECT_EQ(r.out.rfind("beamtrace: ", 0), 0u) << r.out;
        EXPECT_NE(r.out.find("--outputs"), std::string::npos) << r.out;
        EXPECT_FALSE(fs::exists(out)) << bad;
    }
    const auto r = run("scan --demo --quiet --outputs las --output " + out);
    EXPECT_NE(r.out.find("unknown output 'las'"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("ply, npy, png, csv and laz"), std::string::npos) << r.out;
    EXPECT_NE(run("scan --demo --quiet --outputs ply,ply --output " + out).out.find("twice"),
              std::string::npos);
}

// No room for an output (a file-size limit of 128 KiB, SIGXFSZ ignored: what a full disk or a
// quota does) or a folder that cannot be written: a one-line error naming the file, exit 2, and
// nothing left, not even a temporary file or the folder the run created. points.ply and
// range.npy (0.8 MB each here) are reserved at their full size before anything is written.
TEST(ScanOutputs, NoRoomOrAReadOnlyFolderIsAOneLineErrorWithExit2AndLeavesNothing) {
    test::TempDir dir;
    const std::string scan = std::string(BEAMTRACE_CLI_PATH) + " scan --demo --quiet ";
    for (const std::string file : {"points.ply", "range.npy"}) {
        const fs::path out = dir / "new";
        const std::string outputs = file == "points.ply" ? "ply" : "npy";
        const auto r = test::run_command("trap '' XFSZ; ulimit -f 128; " + scan + "--outputs " +
                                         outputs + " --output " + out.string());
        EXPECT_EQ(r.exit_code, 2) << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
        EXPECT_EQ(
            r.out.rfind("beamtrace: error: " + (out / file).string() + ": cannot reserve ", 0), 0u)
            << r.out;
        EXPECT_NE(r.out.find("File too large"), std::string::npos) << r.out;
        EXPECT_FALSE(fs::exists(out)) << r.out;
    }
    if (::geteuid() != 0) {  // root writes anywhere
        fs::create_directories(dir / "ro");
        fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
        const auto r = run("scan --demo --quiet --output " + (dir / "ro").string());
        EXPECT_EQ(r.exit_code, 2) << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
        EXPECT_NE(r.out.find((dir / "ro").string()), std::string::npos) << r.out;
        EXPECT_EQ(test::entry_count(dir / "ro"), 0u);
        fs::permissions(dir / "ro", fs::perms::owner_all);
    }
}

/// The points.ply records of the rays in hits.csv, as the serial writer encodes them: each hit
/// not in [skip_lo, skip_hi] at its range along its ray.
std::string expected_ply_body(const HitsCsv& hits, const RayBatch& rays, std::uint32_t skip_lo,
                              std::uint32_t skip_hi, std::size_t& points) {
    std::vector<PointRecord> records;
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const auto face = hits.face_id[i];
        if (face < 0 || (face >= skip_lo && face <= skip_hi)) {
            continue;
        }
        // The shortest form of the float range reads back as that float exactly.
        const auto t = static_cast<float>(hits.range_m[i]);
        const double td = t;
        records.push_back({rays.ox[i] + td * rays.dx[i], rays.oy[i] + td * rays.dy[i],
                           rays.oz[i] + td * rays.dz[i], t, static_cast<std::uint32_t>(face),
                           static_cast<std::uint32_t>(i)});
    }
    points = records.size();
    std::string body(records.size() * kPlyRecordBytes, '\0');
    encode_ply_records(records, body.data());
    return body;
}

// 400 x 300 rays: two chunks of 65536 and a partial one, so the records of each chunk land at
// offsets the other chunks' counts decide; faces of the occluding plane excluded.
TEST(ScanOutputs, ParallelWritersGiveTheSerialWritersBytesAtAnyThreadCount) {
    test::TempDir dir;
    const std::string common =
        "scan --demo --width 400 --height 300 --quiet --exclude-faces 80180-80181 "
        "--outputs ply,npy,png,csv --backend bvh ";
    for (const char* t : {"1", "2", "3"}) {
        const auto r = run(common + "--threads " + t + " --output " + (dir / t).string());
        ASSERT_EQ(r.exit_code, 0) << r.out;
    }
    for (const char* f : {"points.ply", "range.npy", "range.png", "hits.csv"}) {
        const std::string one = test::read_file(dir / "1" / f);
        EXPECT_EQ(one, test::read_file(dir / "2" / f)) << f;
        EXPECT_EQ(one, test::read_file(dir / "3" / f)) << f;
    }
    ImageSensorConfig cam = demo_sensor();
    cam.width = 400;
    cam.height = 300;
    const RayBatch rays = cast_rays_pinhole(cam);
    const HitsCsv hits = read_hits_csv(dir / "2" / "hits.csv");
    ASSERT_EQ(hits.size(), rays.size());
    // hits.csv: the serial writer's bytes for the same hits.
    HitBatch batch;
    batch.resize(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        batch.t[i] = static_cast<float>(hits.range_m[i]);
        batch.face[i] = static_cast<std::uint32_t>(hits.face_id[i]);
    }
    write_hits_csv(dir / "serial.csv", batch);
    EXPECT_EQ(test::read_file(dir / "2" / "hits.csv"), test::read_file(dir / "serial.csv"));
    // points.ply: the serial encoder's records after the header, the count in the header.
    std::size_t points = 0;
    const std::string body = expected_ply_body(hits, rays, 80180, 80181, points);
    ASSERT_GT(points, 1000u);
    ASSERT_LT(points, 120000u);  // some hits are on the plane
    const std::string ply = test::read_file(dir / "2" / "points.ply");
    const std::size_t end = ply.find("end_header\n") + 11;
    EXPECT_NE(ply.find("element vertex " + std::to_string(points) + "\n"), std::string::npos);
    EXPECT_TRUE(ply.substr(end) == body);
    EXPECT_EQ(read_points_ply(dir / "2" / "points.ply").size(), points);
    // range.npy: the serial writer's file of the image of every hit (plane included).
    std::vector<float> image(rays.size(), 0.0f);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (hits.face_id[i] >= 0) {
            image[(i % 300) * 400 + i / 300] = static_cast<float>(hits.range_m[i]);
        }
    }
    write_npy_f32(dir / "serial.npy", 300, 400, image);
    EXPECT_TRUE(test::read_file(dir / "2" / "range.npy") == test::read_file(dir / "serial.npy"));
    // range.png, decoded by libpng: the colour map of that image, the colour bar below it.
    const RgbImage png = read_png_rgb8(dir / "2" / "range.png");
    EXPECT_EQ(png.width, 400);
    ASSERT_GT(png.height, 300);
    const std::vector<std::uint8_t> rgb = range_image_rgb(image, 400, 300);
    EXPECT_TRUE(std::equal(rgb.begin(), rgb.end(), png.rgb.begin()));
}

}  // namespace
}  // namespace beamtrace
