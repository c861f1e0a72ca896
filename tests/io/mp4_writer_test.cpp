#include "beamtrace/io/mp4_writer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/png_reader.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

class Mp4Video : public test::TempDirTest {
  protected:
    void SetUp() override {
        if (!find_ffmpeg() || test::run_command("command -v ffprobe").exit_code != 0) {
            BEAMTRACE_SKIP_OR_FAIL("ffmpeg/ffprobe not installed (apt install ffmpeg)");
        }
    }
    [[nodiscard]] static std::vector<std::uint8_t> frame(int w, int h, int k) {
        std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w * h * 3));
        for (std::size_t i = 0; i < rgb.size(); ++i) {
            rgb[i] = static_cast<std::uint8_t>((i / 3 + static_cast<std::size_t>(k) * 7) % 251);
        }
        return rgb;
    }
};

TEST_F(Mp4Video, EncodesEveryFrameAndRenamesOnCommit) {
    const auto path = dir_ / "v.mp4";
    {
        Mp4Writer video(path, 33, 17, 12.0);  // odd sizes: padded to 34 x 18
        for (int k = 0; k < 5; ++k) {
            video.write(frame(33, 17, k));
        }
        EXPECT_FALSE(std::filesystem::exists(path));  // only the temporary file so far
        video.commit();
        EXPECT_EQ(video.frames(), 5);
    }
    const auto r = test::run_command(
        "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
        "stream=width,height,nb_read_frames,r_frame_rate,pix_fmt -of csv=p=0 '" +
        path.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(r.out, "34,18,yuv420p,12/1,5\n");
    EXPECT_EQ(test::entry_count(dir_.path()), 1u);  // no temporary or log file left
}

TEST_F(Mp4Video, WithoutCommitNothingIsLeft) {
    {
        Mp4Writer video(dir_ / "v.mp4", 16, 16, 25.0);
        video.write(frame(16, 16, 0));
    }
    EXPECT_EQ(test::entry_count(dir_.path()), 0u);
}

TEST_F(Mp4Video, AFailingFfmpegIsAnErrorNotADeadProcess) {
    // The temporary name is taken by a directory: ffmpeg cannot open its output and exits, and
    // the writes into its pipe fail (SIGPIPE must not kill the test).
    const auto path = dir_ / "v.mp4";
    std::filesystem::create_directory(
        dir_ / ("." + path.filename().string() + "." + std::to_string(::getpid()) + ".tmp"));
    std::string message;
    try {
        Mp4Writer video(path, 320, 240, 25.0);
        for (int k = 0; k < 200; ++k) {
            video.write(frame(320, 240, k));
        }
        video.commit();
    } catch (const OutputError& e) {
        message = e.what();
    }
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("ffmpeg"), std::string::npos) << message;
    EXPECT_FALSE(std::filesystem::exists(path));
}

TEST_F(Mp4Video, FrameOfTheWrongSizeIsRejected) {
    Mp4Writer video(dir_ / "v.mp4", 8, 8, 25.0);
    EXPECT_THROW(video.write(frame(8, 7, 0)), OutputError);
}

TEST(PngReader, ReadsBackWhatTheWriterWrote) {
    test::TempDir dir;
    std::vector<std::uint8_t> rgb(5 * 3 * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        rgb[i] = static_cast<std::uint8_t>(i * 5);
    }
    write_png_rgb8(dir / "a.png", 5, 3, rgb);
    const RgbImage back = read_png_rgb8(dir / "a.png");
    EXPECT_EQ(back.width, 5);
    EXPECT_EQ(back.height, 3);
    EXPECT_EQ(back.rgb, rgb);
    const auto broken = test::write_file(dir / "b.png", "not a png");
    EXPECT_THROW(static_cast<void>(read_png_rgb8(broken)), InputError);
}

}  // namespace
}  // namespace beamtrace
