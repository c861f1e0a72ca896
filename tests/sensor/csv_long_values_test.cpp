// Rays and trajectory CSV errors quote a bad field clipped to 80 characters (issue 15, finding 8).
#include <gtest/gtest.h>

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/rays_file.hpp"
#include "beamtrace/sensor/trajectory.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

template <typename Read>
std::string input_error(Read read, const std::filesystem::path& path) {
    try {
        (void)read(path);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted";
    return {};
}

TEST(CsvLongValues, RaysFieldsAreQuotedClipped) {
    test::TempDir dir;
    const std::string big(std::size_t{1} << 20, '7');
    for (const std::string& bad : {big + "x", big + "e999999"}) {
        test::write_file(dir / "rays.csv", "0,0,0,0,0,1\n" + bad + ",0,0,0,0,1\n");
        const std::string msg = input_error(read_rays_csv, dir / "rays.csv");
        EXPECT_NE(msg.find(":2: "), std::string::npos) << msg.substr(0, 300);
        EXPECT_NE(msg.find("'" + std::string(80, '7') + "...' in field 1 (ox)"), std::string::npos)
            << msg.substr(0, 300);
        EXPECT_LT(msg.size(), 300u) << msg.substr(0, 300);
    }
}

TEST(CsvLongValues, TrajectoryFieldsAreQuotedClipped) {
    test::TempDir dir;
    const std::string big(std::size_t{1} << 20, '5');
    test::write_file(dir / "t.csv",
                     "time_s,x,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0\n1,0," + big + "x,0,0,0,0\n");
    const std::string msg = input_error(read_trajectory_csv, dir / "t.csv");
    EXPECT_NE(msg.find(":3: field 'y' is not a finite number: '" + std::string(80, '5') + "...'"),
              std::string::npos)
        << msg.substr(0, 300);
    test::write_file(dir / "t.csv",
                     "time_s,x,y,z,roll,pitch,yaw\n1,0,0,0,0,0,0\n0" + big + ",0,0,0,0,0,0\n");
    const std::string later = input_error(read_trajectory_csv, dir / "t.csv");
    EXPECT_LT(later.size(), 300u) << later.substr(0, 300);
}

}  // namespace
}  // namespace beamtrace
