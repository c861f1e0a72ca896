// Tiny files that claim huge sizes, and numbers beyond float, fed to the CLI: each is refused
// with exit code 2 and one line naming the file, nothing written, and a peak memory far below
// what the claim would take (issue 15, findings 4, 6, 8 and 9).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "../heightfield/child_peak_rss.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kPeakLimitBytes = 100u << 20;

template <typename T>
void append(std::string& out, T value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

/// A little-endian TIFF of one uncompressed int16 strip (one sample) whose header claims
/// `width` x `height` cells.
std::string tiff_claiming(std::uint32_t width, std::uint32_t height) {
    struct Entry {
        std::uint16_t tag, type;
        std::uint32_t value;
    };
    const std::vector<Entry> entries{
        {256, 4, width}, {257, 4, height}, {258, 3, 16},     {259, 3, 1}, {262, 3, 1},
        {273, 4, 8},     {277, 3, 1},      {278, 4, height}, {279, 4, 2}, {339, 3, 2}};
    std::string out = "II";
    append(out, std::uint16_t{42});
    append(out, std::uint32_t{10});  // the IFD after the 2-byte strip
    append(out, std::int16_t{7});
    append(out, static_cast<std::uint16_t>(entries.size()));
    for (const Entry& e : entries) {
        append(out, e.tag);
        append(out, e.type);
        append(out, std::uint32_t{1});
        if (e.type == 3) {
            append(out, static_cast<std::uint16_t>(e.value));
            append(out, std::uint16_t{0});
        } else {
            append(out, e.value);
        }
    }
    append(out, std::uint32_t{0});
    return out;
}

/// An empty LAS 1.4 file whose point data offset lies past its end.
std::string las_with_offset_past_the_end(const fs::path& dir) {
    const fs::path path = dir / "empty.las";
    LasWriter writer(path, {});
    writer.close();
    std::string bytes = test::read_file(path);
    fs::remove(path);
    const std::uint32_t offset = 1'000'000;
    std::memcpy(bytes.data() + 96, &offset, sizeof offset);
    return bytes;
}

class HostileSizes : public test::TempDirTest {
  protected:
    /// Runs `beamtrace args...` and expects exit 2, one line naming `named` (and `fragment`),
    /// no "internal error", nothing under `output` and a peak RSS under 100 MB.
    void expect_refused(const std::vector<std::string>& args, const fs::path& named,
                        const std::string& fragment, const fs::path& output = {}) const {
        std::vector<std::string> argv{BEAMTRACE_CLI_PATH};
        argv.insert(argv.end(), args.begin(), args.end());
        const fs::path log = dir_ / "log.txt";
        const test::ChildPeak run = test::run_measuring_peak_rss(argv, log);
        ASSERT_TRUE(run.error.empty()) << run.error;
        const std::string out = test::read_file(log);
        EXPECT_EQ(run.exit_code, 2) << out;
        EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
        EXPECT_NE(out.find("beamtrace: error: "), std::string::npos) << out;
        EXPECT_NE(out.find(named.string()), std::string::npos) << out;
        EXPECT_NE(out.find(fragment), std::string::npos) << out;
        EXPECT_EQ(out.find("internal error"), std::string::npos) << out;
#ifndef BEAMTRACE_SANITIZED  // AddressSanitizer's shadow memory swamps the RSS
        EXPECT_GT(run.peak_rss_bytes, 0u);
        EXPECT_LT(run.peak_rss_bytes, kPeakLimitBytes) << out;
#endif
        if (!output.empty()) {
            EXPECT_TRUE(!fs::exists(output) || fs::is_empty(output)) << output;
        }
    }

    /// A survey of `scene_yaml` with a small static scanner; its scene file named in errors.
    [[nodiscard]] std::vector<std::string> survey_of_scene(const std::string& scene_yaml) const {
        static_cast<void>(write("scene.yaml", scene_yaml));
        const fs::path survey =
            write("survey.yaml",
                  "scene: scene.yaml\nscanner:\n  type: scan\n  width: 36\n  height: 10\n"
                  "  hfov_deg: 360\n  vfov_deg: 90\n  pulse_rate_hz: 1000\n"
                  "platform:\n  type: static\n  position_m: [0, 0, 2]\n");
        return {"survey", survey.string(), "--output", (dir_ / "out").string()};
    }
};

TEST_F(HostileSizes, GeoTiffClaimingAHugeRaster) {
    const fs::path tif = write("huge.tif", tiff_claiming(65536, 65536));
    EXPECT_LT(fs::file_size(tif), 200u);
    expect_refused(survey_of_scene("parts:\n  - raster: huge.tif\n"), tif,
                   "above the limit of 268435456 cells", dir_ / "out");
    // Under the cell limit, the samples cannot lie in the file.
    const fs::path big = write("big.tif", tiff_claiming(10000, 10000));
    expect_refused(survey_of_scene("parts:\n  - raster: big.tif\n"), big, "lie outside the file",
                   dir_ / "out");
}

TEST_F(HostileSizes, AsciiGridClaimingAHugeRaster) {
    const fs::path asc =
        write("huge.asc", "ncols 65536\nnrows 65536\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n");
    EXPECT_EQ(fs::file_size(asc), 61u);
    expect_refused(survey_of_scene("parts:\n  - raster: huge.asc\n"), asc,
                   "ncols x nrows = 4294967296 cells is above the limit", dir_ / "out");
    const fs::path big =
        write("big.asc", "ncols 10000\nnrows 10000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n");
    expect_refused(survey_of_scene("parts:\n  - raster: big.asc\n"), big,
                   "values cannot fit in the 2 bytes after the header", dir_ / "out");
}

TEST_F(HostileSizes, SphereAndScaleBeyondFloat) {
    const auto args = survey_of_scene(
        "parts:\n  - sphere: {center_m: [1e300, 0, 0], radius_m: 1}\n    name: far\n");
    expect_refused(args, dir_ / "scene.yaml", "part 'far': center_m (1e+300, 0, 0)", dir_ / "out");
    static_cast<void>(write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    expect_refused(survey_of_scene("parts:\n  - mesh: tri.obj\n    name: big\n"
                                   "    transform: {scale: 1e40}\n"),
                   dir_ / "scene.yaml", "part 'big': scale", dir_ / "out");
}

TEST_F(HostileSizes, NanVertexInAMesh) {
    const fs::path obj = write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    const fs::path out = dir_ / "scan_out";
    expect_refused({"scan", "--mesh", obj.string(), "--output", out.string()}, obj,
                   "not a finite float", out);
    const fs::path ply = write("nan.ply",
                               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                               "property float y\nproperty float z\nelement face 1\n"
                               "property list uchar int vertex_indices\nend_header\n"
                               "0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n");
    expect_refused({"scan", "--mesh", ply.string(), "--output", out.string()}, ply,
                   "not a finite float", out);
}

TEST_F(HostileSizes, OneFrameImageScannerAboveThePixelLimit) {
    const fs::path survey =
        write("image.yaml",
              "scene: demo\nscanner:\n  type: scan\n  width: 40000\n  height: 40000\n"
              "  hfov_deg: 360\n  vfov_deg: 90\n  pulse_rate_hz: 1000000\n"
              "platform:\n  type: static\n  position_m: [0, 0, 2]\n");
    const fs::path out = dir_ / "out";
    expect_refused({"survey", survey.string(), "--output", out.string()}, survey,
                   "width x height of one frame (40000 x 40000) must be at most 67108864 pixels",
                   out);
}

TEST_F(HostileSizes, LasWithThePointDataOffsetPastTheEnd) {
    const fs::path las = write("past.las", las_with_offset_past_the_end(dir_.path()));
    expect_refused({"info", las.string()}, las,
                   "point data offset 1000000 lies past the end of the file (375 bytes)");
}

#ifndef BEAMTRACE_SANITIZED  // AddressSanitizer cannot run under a small address-space limit
TEST_F(HostileSizes, OutOfMemoryNamesWhatRanOutOfIt) {
    // A one-frame image of 8192 x 8192 pixels (the limit) in 600 MB of address space: its range
    // and label images cannot be allocated.
    const fs::path survey =
        write("image.yaml",
              "scene: demo\nscanner:\n  type: scan\n  width: 8192\n  height: 8192\n"
              "  hfov_deg: 360\n  vfov_deg: 90\n  pulse_rate_hz: 1000000\n"
              "platform:\n  type: static\n  position_m: [0, 0, 2]\n");
    const fs::path out = dir_ / "out";
    const test::RunResult r =
        test::run_command("ulimit -v 600000; " + std::string(BEAMTRACE_CLI_PATH) + " survey " +
                          survey.string() + " --output " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;
    // Either the images (named by their file and the setting) or, failing earlier, the command.
    const bool images = r.out.find((out / "range.npy").string() +
                                   ": out of memory for the 8192 x 8192 range and label images "
                                   "(the scanner's width x height)") != std::string::npos;
    const bool command =
        r.out.find("out of memory running 'survey " + survey.string()) != std::string::npos;
    EXPECT_TRUE(images || command) << r.out;
    EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out)) << out;
}
#endif

}  // namespace
}  // namespace beamtrace
