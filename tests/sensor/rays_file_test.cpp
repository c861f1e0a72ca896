#include "beamtrace/sensor/rays_file.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

class RaysFile : public test::TempDirTest {
  protected:
    /// Writes `text` to a file and reads it back.
    RayBatch parse(const std::string& text) { return read_rays_csv(test::write_file(path_, text)); }

    /// Expects `text` to fail at `line` (0: no line) with a message containing `fragment`.
    void expect_error(const std::string& text, long line, const std::string& fragment) {
        const std::string message =
            test::expect_input_error(read_rays_csv, test::write_file(path_, text), fragment);
        const std::string location =
            line > 0 ? path_.string() + ":" + std::to_string(line) + ":" : path_.string() + ":";
        EXPECT_EQ(message.rfind(location, 0), 0u) << message;
    }

    fs::path path_ = dir_ / "rays.csv";
};

TEST_F(RaysFile, ParsesPlainLines) {
    const RayBatch rays = parse("0,0,0,1,0,0\n1.5,-2,3e2,0,0,-1\n");
    ASSERT_EQ(rays.size(), 2u);
    EXPECT_EQ(rays.origin(1), (Vec3d{1.5, -2.0, 300.0}));
    EXPECT_EQ(rays.direction(0), (Vec3d{1.0, 0.0, 0.0}));
    EXPECT_EQ(rays.direction(1), (Vec3d{0.0, 0.0, -1.0}));
    EXPECT_EQ(rays.tmin[1], 0.0);
    EXPECT_EQ(rays.tmax[1], std::numeric_limits<double>::infinity());
}

TEST_F(RaysFile, AcceptsSpacesCommentsBlankLinesHeaderAndCrlf) {
    const RayBatch rays = parse(
        "# exported by some tool\r\n"
        "\r\n"
        "ox, oy, oz, dx, dy, dz\r\n"
        "  1 ,\t2 , 3,  0 , +1 ,0  \r\n"
        "   # indented comment\n"
        "\n"
        "4,5,6,0,0,1");  // no final newline
    ASSERT_EQ(rays.size(), 2u);
    EXPECT_EQ(rays.origin(0), (Vec3d{1.0, 2.0, 3.0}));
    EXPECT_EQ(rays.direction(0), (Vec3d{0.0, 1.0, 0.0}));
    EXPECT_EQ(rays.origin(1), (Vec3d{4.0, 5.0, 6.0}));
}

TEST_F(RaysFile, HeaderMayFollowComments) {
    const RayBatch rays = parse("# comment\nox,oy,oz,dx,dy,dz\n0,0,0,0,2,0\n");
    ASSERT_EQ(rays.size(), 1u);
}

TEST_F(RaysFile, LinesLongerThanTheReadBufferAndManyChunks) {
    std::string text = "#" + std::string(3'000'000, 'x') + "\n";  // longer than one chunk
    for (int i = 0; i < 100'000; ++i) {
        text += std::to_string(i) + ",0,0,0,0,1\n";
    }
    text += "1,2,3, 4,5,6 \t  " + std::string(2'000'000, ' ') + "\n";
    text += "0,0,0,0,0,1,extra\n";
    expect_error(text, 100'003, "found 7");
    text.resize(text.size() - 18);
    const RayBatch rays = parse(text);
    ASSERT_EQ(rays.size(), 100'001u);
    EXPECT_EQ(rays.ox[99'999], 99'999.0);
    EXPECT_EQ(rays.origin(100'000), (Vec3d{1.0, 2.0, 3.0}));
}

TEST_F(RaysFile, NormalisesDirections) {
    const RayBatch rays = parse("0,0,0,3,4,0\n0,0,0,1e-300,1e-300,0\n0,0,0,1e300,-1e300,1e300\n");
    ASSERT_EQ(rays.size(), 3u);
    EXPECT_DOUBLE_EQ(rays.dx[0], 0.6);
    EXPECT_DOUBLE_EQ(rays.dy[0], 0.8);
    EXPECT_DOUBLE_EQ(rays.dx[1], std::sqrt(0.5));
    EXPECT_DOUBLE_EQ(rays.dy[1], std::sqrt(0.5));
    EXPECT_DOUBLE_EQ(rays.dy[2], -1.0 / std::sqrt(3.0));
    for (std::size_t i = 0; i < rays.size(); ++i) {
        EXPECT_NEAR(length(rays.direction(i)), 1.0, 1e-15) << "ray " << i;
    }
}

TEST_F(RaysFile, WrongFieldCountNamesFileAndLine) {
    expect_error("0,0,0,1,0,0\n\n0,0,0,1,0\n", 3, "found 5");
    expect_error("0,0,0,1,0,0,7\n", 1, "found 7");
    expect_error("# c\n0 0 0 1 0 0\n", 2, "found 1");
}

TEST_F(RaysFile, MalformedNumberNamesFileAndLine) {
    expect_error("0,0,0,1,0,0\n0,0,zero,1,0,0\n", 2, "malformed number 'zero' in field 3 (oz)");
    expect_error("0,0,0,1,0,0\n0,0,0,1.0.0,0,0\n", 2, "field 4 (dx)");
    expect_error("0,0,0,1,0,0\n0,,0,1,0,0\n", 2, "field 2 (oy)");
    expect_error("0,0,0,1,0,0\n0,0,0,1,0,0x1\n", 2, "field 6 (dz)");
    expect_error("0,0,0,1,0,0\n0,0,0,1,0,1e999\n", 2, "out of range");
    // A header is only allowed before the first ray.
    expect_error("0,0,0,1,0,0\nox,oy,oz,dx,dy,dz\n", 2, "malformed number");
    // A first line with some numbers is data, not a header.
    expect_error("ox,1,2,3,4,5\n", 1, "malformed number 'ox'");
}

TEST_F(RaysFile, NonFiniteValuesNameFileAndLine) {
    expect_error("0,0,0,1,0,0\n0,nan,0,1,0,0\n", 2, "non-finite");
    expect_error("0,0,0,1,0,0\n\n0,0,0,inf,0,0\n", 3, "non-finite");
    expect_error("-inf,0,0,1,0,0\n", 1, "non-finite");
}

TEST_F(RaysFile, ZeroDirectionNamesFileAndLine) {
    expect_error("# header comment\n1,2,3,0,0,0\n", 2, "zero-length direction");
    expect_error("1,2,3,0,-0,0.0\n", 1, "zero-length direction");
}

TEST_F(RaysFile, FileWithoutRaysIsAnError) {
    expect_error("", 0, "no rays");
    expect_error("# only a comment\n\n", 0, "no rays");
    expect_error("ox,oy,oz,dx,dy,dz\n", 0, "no rays");
}

TEST_F(RaysFile, UnreadableFileIsAnError) {
    test::expect_input_error(read_rays_csv, dir_ / "missing.csv");
    EXPECT_THROW(static_cast<void>(read_rays_csv(dir_.path())), InputError);
}

TEST_F(RaysFile, WriteReadRoundTripIsBitExact) {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> position(-1e4, 1e4);
    std::normal_distribution<double> gaussian;
    RayBatch rays;
    rays.push_back({0.1, -0.0, std::numeric_limits<double>::denorm_min()}, {0.0, 0.0, 1.0});
    rays.push_back({std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                    std::numeric_limits<double>::min()},
                   normalize(Vec3d{1.0, 1.0, 1.0}));
    for (int i = 0; i < 20'000; ++i) {
        const Vec3d o{position(rng), position(rng), position(rng)};
        const Vec3d d = normalize(Vec3d{gaussian(rng), gaussian(rng), gaussian(rng)});
        rays.push_back(o, d);
    }
    write_rays_csv(path_, rays);
    EXPECT_EQ(test::read_file(path_).substr(0, 38), "ox,oy,oz,dx,dy,dz\n0.1,-0,5e-324,0,0,1\n");

    const RayBatch back = read_rays_csv(path_);
    ASSERT_EQ(back.size(), rays.size());
    const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(bits(back.ox[i]), bits(rays.ox[i])) << "ray " << i;
        ASSERT_EQ(bits(back.oy[i]), bits(rays.oy[i])) << "ray " << i;
        ASSERT_EQ(bits(back.oz[i]), bits(rays.oz[i])) << "ray " << i;
        ASSERT_EQ(bits(back.dx[i]), bits(rays.dx[i])) << "ray " << i;
        ASSERT_EQ(bits(back.dy[i]), bits(rays.dy[i])) << "ray " << i;
        ASSERT_EQ(bits(back.dz[i]), bits(rays.dz[i])) << "ray " << i;
    }
}

TEST_F(RaysFile, WriterRejectsNonFiniteValuesAndMalformedBatches) {
    RayBatch rays;
    rays.push_back({0.0, 0.0, 0.0}, {1.0, 0.0, 0.0});
    rays.push_back({0.0, std::numeric_limits<double>::quiet_NaN(), 0.0}, {1.0, 0.0, 0.0});
    try {
        write_rays_csv(path_, rays);
        ADD_FAILURE() << "expected OutputError";
    } catch (const OutputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(path_.string()), std::string::npos) << message;
        EXPECT_NE(message.find("ray 1"), std::string::npos) << message;
    }
    EXPECT_FALSE(fs::exists(path_));
    rays.oy[1] = 0.0;
    rays.dz.pop_back();
    EXPECT_THROW(write_rays_csv(path_, rays), OutputError);
    EXPECT_FALSE(fs::exists(path_));
}

}  // namespace
}  // namespace beamtrace
