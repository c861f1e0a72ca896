#include <gtest/gtest.h>

#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/heightfield/view_session.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/png_reader.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

class ViewCli : public test::TempDirTest {
  protected:
    void SetUp() override {
        las_ = test::shared_data("las/las/autzen_trim.las");
        BEAMTRACE_REQUIRE_FILE(las_);
    }
    [[nodiscard]] std::string cli() const {
        return std::string(BEAMTRACE_CLI_PATH) + " view '" + las_.string() +
               "' --cell-size 2 --levels 5 --section-cells 16 --size 160x90 --threads 2 ";
    }
    std::filesystem::path las_;
};

TEST_F(ViewCli, WritesAPngFromOneCamera) {
    const auto out = dir_ / "view.png";
    const auto r = test::run_command(cli() +
                                     "--camera 636600,849200,900,-30,-60 --fov 70 "
                                     "--color rgb --fog 3000 --output '" +
                                     out.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const std::string png = test::read_file(out);
    ASSERT_GT(png.size(), 100u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    EXPECT_NE(r.out.find("wrote"), std::string::npos) << r.out;
}

TEST_F(ViewCli, WritesOneFramePerPathRow) {
    const auto path = test::write_file(dir_ / "path.csv",
                                       "x,y,z,yaw,pitch\n"
                                       "636100,848950,600,-30,-20\n"
                                       "636300,849050,580,-40,-25\n");
    const auto frames = dir_ / "frames";
    const auto r = test::run_command(cli() + "--path '" + path.string() + "' --output '" +
                                     frames.string() + "' --memory-budget 64MB --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(std::filesystem::exists(frames / "frame_00000.png"));
    EXPECT_TRUE(std::filesystem::exists(frames / "frame_00001.png"));
    EXPECT_EQ(test::entry_count(frames), 2u);
}

TEST_F(ViewCli, WritesAnMp4OfThePathWithFfmpeg) {
    if (test::run_command("command -v ffmpeg && command -v ffprobe").exit_code != 0) {
        BEAMTRACE_SKIP_OR_FAIL("ffmpeg/ffprobe not installed (apt install ffmpeg)");
    }
    const auto path = test::write_file(dir_ / "path.csv",
                                       "x,y,z,yaw,pitch\n"
                                       "636100,848950,600,-30,-20\n"
                                       "636200,849000,590,-35,-22\n"
                                       "636300,849050,580,-40,-25\n");
    const auto video = dir_ / "fly.mp4";
    auto r =
        test::run_command(cli() + "--path '" + path.string() + "' --output '" +
                          (dir_ / "frames").string() + "' --mp4 '" + video.string() + "' --fps 10");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("3 frames"), std::string::npos) << r.out;
    r = test::run_command(
        "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
        "stream=width,height,nb_read_frames,r_frame_rate -of csv=p=0 '" +
        video.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(r.out, "160,90,10/1,3\n");
    // Written under a temporary name and renamed: nothing else is left behind.
    EXPECT_EQ(test::entry_count(dir_.path()), 3u);  // path.csv, frames/, fly.mp4
}

TEST_F(ViewCli, Mp4WithoutFfmpegIsAClearError) {
    const auto path =
        test::write_file(dir_ / "path.csv", "x,y,z,yaw,pitch\n636100,848950,600,-30,-20\n");
    const auto r = test::run_command("PATH=/nonexistent-beamtrace-dir " + cli() + "--path '" +
                                     path.string() + "' --output '" + (dir_ / "frames").string() +
                                     "' --mp4 '" + (dir_ / "x.mp4").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find("needs ffmpeg on PATH"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "frames"));
    EXPECT_FALSE(std::filesystem::exists(dir_ / "x.mp4"));
}

TEST_F(ViewCli, ErrorsAreOneLineNamingTheFile) {
    const auto broken = test::write_file(dir_ / "broken.las", "LASF");
    auto r =
        test::run_command(std::string(BEAMTRACE_CLI_PATH) + " view '" + broken.string() +
                          "' --camera 0,0,10,0,-90 --output '" + (dir_ / "x.png").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find(broken.string()), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "x.png"));

    const auto bad_path = test::write_file(dir_ / "bad.csv", "x,y,z,yaw,pitch\n1,2,3,4\n");
    r = test::run_command(cli() + "--path '" + bad_path.string() + "' --output '" +
                          (dir_ / "f").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find(bad_path.string() + ":2:"), std::string::npos) << r.out;

    r = test::run_command(cli() + "--camera 1,2,3,0,-90 --memory-budget lots --output '" +
                          (dir_ / "y.png").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find("memory budget"), std::string::npos) << r.out;
}

/// `beamtrace view --height-stacks` end to end (so the ASan build runs it too): ground at z = 0
/// over [0.5, 32.5)^2 and a 10 m high bridge deck over x in [14.5, 18.5), seen at a grazing
/// angle from under the deck's height. The CLI's image equals the library's render with the
/// same stacks, and differs from the image without stacks where the rays pass under the deck.
class ViewCliStacks : public test::TempDirTest {
  protected:
    void SetUp() override { las_ = test::write_bridge_las(dir_ / "bridge.las"); }

    /// The CLI's PNG with `stacks` height stacks (0: none).
    [[nodiscard]] RgbImage cli_image(int stacks) const {
        const auto out = dir_ / ("stacks" + std::to_string(stacks) + ".png");
        const auto r = test::run_command(
            std::string(BEAMTRACE_CLI_PATH) + " view '" + las_.string() +
            "' --cell-size 1 --levels 3 --section-cells 8 --sections 2x2 --height-stacks " +
            std::to_string(stacks) + " --stack-gap 1 --camera 2,16.3,4,0,-10 --fov 60 " +
            "--size 101x51 --threads 2 --output '" + out.string() + "'");
        EXPECT_EQ(r.exit_code, 0) << r.out;
        return read_png_rgb8(out);
    }

    /// The same view rendered by the library.
    [[nodiscard]] ViewImage library_image(int stacks) const {
        const ViewSessionConfig c = test::bridge_view_config(stacks);
        ViewSession session(std::span(&las_, 1), c);
        static_cast<void>(session.move_to({2.0, 16.3, 4.0}));
        ViewCamera cam;
        cam.position = {2.0, 16.3, 4.0};
        cam.pitch_deg = -10.0;
        cam.hfov_deg = 60.0;
        cam.width = 101;
        cam.height = 51;
        return session.render(cam, {});
    }

    std::filesystem::path las_;
};

TEST_F(ViewCliStacks, HeightStacksOnTheCommandLineRenderUnderTheBridge) {
    const RgbImage stacked = cli_image(2);
    const RgbImage columns = cli_image(0);
    ASSERT_EQ(stacked.width, 101);
    ASSERT_EQ(stacked.height, 51);
    EXPECT_EQ(stacked.rgb, library_image(2).rgb) << "the CLI's stacks differ from the library's";
    EXPECT_EQ(columns.rgb, library_image(0).rgb);
    // The middle pixel looks under the deck: with stacks it sees the ground beyond, without
    // them the side of the deck's column. Many pixels around it differ the same way.
    const std::size_t middle = 3 * (25 * 101 + 50);
    EXPECT_NE(
        std::vector<std::uint8_t>(stacked.rgb.begin() + middle, stacked.rgb.begin() + middle + 3),
        std::vector<std::uint8_t>(columns.rgb.begin() + middle, columns.rgb.begin() + middle + 3));
    std::size_t differ = 0;
    for (std::size_t i = 0; i < stacked.rgb.size(); i += 3) {
        differ += stacked.rgb[i] != columns.rgb[i] || stacked.rgb[i + 1] != columns.rgb[i + 1] ||
                  stacked.rgb[i + 2] != columns.rgb[i + 2];
    }
    EXPECT_GT(differ, 101u * 51u / 20) << "stacks change only " << differ << " pixels";
    std::printf("[ stacks   ] --height-stacks 2 changes %zu of %d pixels\n", differ, 101 * 51);
}

}  // namespace
}  // namespace beamtrace
