// What a survey writes, checked against independent sources: closed-form geometry, hand-written
// trajectories and rasters, and the LAS 1.4 / waveforms.bin / PLY layouts parsed from their
// specifications (survey_outputs_support.hpp), never with the library's own readers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "pipeline/survey_outputs_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kLightMps = 299792458.0;

/// Splits one CSV line into numbers.
std::vector<double> csv_numbers(const std::string& line) {
    std::vector<double> v;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, ',')) {
        v.push_back(std::stod(field));
    }
    return v;
}

/// The rows of a CSV file after its header line.
std::vector<std::vector<double>> csv_rows(const std::string& text) {
    std::vector<std::vector<double>> rows;
    std::stringstream ss(text);
    std::string line;
    std::getline(ss, line);
    while (std::getline(ss, line)) {
        rows.push_back(csv_numbers(line));
    }
    return rows;
}

// ---------------------------------------------------------------------------------------------
// 1. A platform replaying a trajectory file.

/// The hand-written trajectory: level, facing +x, 20 m/s along x for 0.5 s, then 40 m/s along y
/// while climbing 20 m/s. Linear between the rows.
Vec3d platform_at(double t) {
    if (t <= 0.5) {
        return {20.0 * t, 0.0, 50.0};
    }
    return {10.0, 40.0 * (t - 0.5), 50.0 + 20.0 * (t - 0.5)};
}

constexpr const char* kPoses = R"(time_s,x,y,z,roll,pitch,yaw
0,0,0,50,0,0,0
0.5,10,0,50,0,0,0
1.0,10,20,60,0,0,0
)";

constexpr const char* kGround =
    "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 400}\n";

TEST(SurveyOutputs, TrajectoryFileGivesTheSensorPositionAndTimeOfEveryPulse) {
    test::TempDir dir;
    test::write_file(dir / "ground.yaml", kGround);
    test::write_file(dir / "poses.csv", kPoses);
    // A line scanner looking down (boresight pitch -90: its sweep plane is the world y-z plane,
    // the attitude being constant), 1 m ahead, 2 m left and 1 m below the platform's origin.
    const test::RawLas las = test::run_survey_raw(R"(scene: ground.yaml
scanner: {type: line, pulse_rate_hz: 2000, scan_rate_hz: 20, scan_angle_max_deg: 20, waveform: sawtooth, duration_s: 1.0}
platform: {type: trajectory, file: poses.csv}
mount: {lever_arm_m: [1, 2, -1], boresight_deg: [0, -90, 0]}
output: {csv: true, trajectory_rate_hz: 4}
)",
                                                  dir);
    ASSERT_EQ(las.points.size(), 2000u) << "every pulse reaches the ground";
    const auto csv = csv_rows(test::read_file(dir / "out" / "points.csv"));
    ASSERT_EQ(csv.size(), las.points.size());
    for (std::size_t k = 0; k < las.points.size(); ++k) {
        const test::RawLasPoint& p = las.points[k];
        const double t = static_cast<double>(k) / 2000.0;  // pulse k fires at k / rate
        ASSERT_DOUBLE_EQ(p.gps_time, t) << k;
        const Vec3d sensor = platform_at(t) + Vec3d{1, 2, -1};
        // The beam stays in the plane x = sensor x and ends on the ground at its range.
        ASSERT_NEAR(p.x, sensor.x, 1e-3) << k;
        ASSERT_NEAR(p.z, 0.0, 1e-3) << k;
        const double half_swath = sensor.z * std::tan(20.0 / kRadToDeg);
        ASSERT_LE(std::abs(p.y - sensor.y), half_swath + 1e-3) << k;
        const double range = length(Vec3d{p.x, p.y, p.z} - sensor);
        ASSERT_NEAR(csv[k][4], range, 2e-3) << "range_m of pulse " << k;
    }
    // trajectory.csv samples the file's poses, interpolated, at 4 Hz over the survey.
    const auto traj = csv_rows(test::read_file(dir / "out" / "trajectory.csv"));
    ASSERT_EQ(traj.size(), 5u);
    for (std::size_t k = 0; k < traj.size(); ++k) {
        const double t = 0.25 * static_cast<double>(k);
        EXPECT_NEAR(traj[k][0], t, 1e-12);
        const Vec3d want = platform_at(t);
        EXPECT_NEAR(traj[k][1], want.x, 1e-9) << t;
        EXPECT_NEAR(traj[k][2], want.y, 1e-9) << t;
        EXPECT_NEAR(traj[k][3], want.z, 1e-9) << t;
    }
}

TEST(SurveyOutputs, TrajectoryFileOutsideTheScannersTimesIsRefused) {
    // The scanner's pulses are timed from 0 s; a trajectory from 100 s to 101 s does not cover
    // them, and the survey is refused before anything is written.
    test::TempDir dir;
    test::write_file(dir / "ground.yaml", kGround);
    test::write_file(dir / "poses.csv",
                     "time_s,x,y,z,roll,pitch,yaw\n100,0,0,50,0,0,0\n101,10,0,50,0,0,0\n");
    try {
        (void)test::run_survey_raw(R"(scene: ground.yaml
scanner: {type: line, pulse_rate_hz: 2000, duration_s: 1.0}
platform: {type: trajectory, file: poses.csv}
)",
                                   dir);
        FAIL() << "expected a ConfigError";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("the platform moves only from 100"), std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "out" / "points.las"));
}

// ---------------------------------------------------------------------------------------------
// 2. A raster terrain at UTM coordinates.

/// An 11 x 11 ESRI ASCII grid with 10 m cells, cell centres from (500000, 5400000): a tilted
/// plane z = 200 + 0.1 (x - 500000) + 0.05 (y - 5400000), exact between the cell centres too.
std::string tilted_grid() {
    std::string asc = "ncols 11\nnrows 11\nxllcenter 500000\nyllcenter 5400000\ncellsize 10\n";
    for (int row = 0; row < 11; ++row) {  // row 0 is the northern edge
        for (int col = 0; col < 11; ++col) {
            const double z = 200.0 + 0.1 * (10.0 * col) + 0.05 * (10.0 * (10 - row));
            asc += (col == 0 ? "" : " ") + std::to_string(z);
        }
        asc += "\n";
    }
    return asc;
}

TEST(SurveyOutputs, RasterAtUtmCoordinatesIsWrittenInUtmAtOneMillimetre) {
    test::TempDir dir;
    test::write_file(dir / "dem.asc", tilted_grid());
    test::write_file(dir / "terrain.yaml", R"(origin_m: [500000, 5400000, 200]
parts:
  - {raster: dem.asc, label: 2}
)");
    // Flying north at 40 m/s, 300 m above the origin (scene coordinates), across the middle.
    const test::RawLas las = test::run_survey_raw(R"(scene: terrain.yaml
scanner: {type: line, pulse_rate_hz: 4000, scan_rate_hz: 40, scan_angle_max_deg: 8, duration_s: 1.0}
platform: {type: legs, speed_mps: 40, waypoints_m: [[50, 10, 300], [50, 90, 300]]}
mount: {boresight_deg: [0, -90, 0]}
output: {trajectory_rate_hz: 1}
)",
                                                  dir);
    // Scale 1 mm; offset = the rounded centre of the terrain's world box
    // [500000, 500100] x [5400000, 5400100] x [200, 215].
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(las.scale[k], 0.001) << k;
    }
    EXPECT_EQ(las.offset[0], 500050.0);
    EXPECT_EQ(las.offset[1], 5400050.0);
    EXPECT_EQ(las.offset[2], 208.0);  // round(207.5)
    ASSERT_EQ(las.points.size(), 4000u);
    for (const auto& p : las.points) {
        ASSERT_GE(p.x, 500000.0);
        ASSERT_LE(p.x, 500100.0);
        ASSERT_GE(p.y, 5400000.0);
        ASSERT_LE(p.y, 5400100.0);
        const double want = 200.0 + 0.1 * (p.x - 500000.0) + 0.05 * (p.y - 5400000.0);
        ASSERT_NEAR(p.z, want, 1.5e-3) << p.x << " " << p.y;
        ASSERT_EQ(p.classification, 2);
    }
    // trajectory.csv is in world coordinates: the first waypoint plus the origin.
    const auto traj = csv_rows(test::read_file(dir / "out" / "trajectory.csv"));
    ASSERT_FALSE(traj.empty());
    EXPECT_DOUBLE_EQ(traj[0][1], 500050.0);
    EXPECT_DOUBLE_EQ(traj[0][2], 5400010.0);
    EXPECT_DOUBLE_EQ(traj[0][3], 500.0);
}

// ---------------------------------------------------------------------------------------------
// 3. Per-point fields, the survey VLR and the GPS-time bit.

// A closed box around (1, 2, 0): floor (part 1), ceiling (part_id 7), four walls (parts 3-6).
constexpr const char* kRoom = R"(parts:
  - {plane: {point_m: [0, 0, -5], normal: [0, 0, 1], size_m: 20}, label: 2}
  - {plane: {point_m: [0, 0, 5], normal: [0, 0, -1], size_m: 20}, label: 3, part_id: 7}
  - {plane: {point_m: [10, 0, 0], normal: [-1, 0, 0], size_m: 20}, label: 6}
  - {plane: {point_m: [-10, 0, 0], normal: [1, 0, 0], size_m: 20}, label: 6}
  - {plane: {point_m: [0, 10, 0], normal: [0, -1, 0], size_m: 20}, label: 6}
  - {plane: {point_m: [0, -10, 0], normal: [0, 1, 0], size_m: 20}, label: 6}
)";

// Four beams, two of them above the horizontal; 1 degree steps at 10 Hz for one revolution:
// 360 firings x 4 beams at 14400 pulses/s.
constexpr double kRoomBeamsDeg[] = {-30, 10, -5, 25};
constexpr double kRoomPulseRate = 14400;

std::string room_survey(int point_format, bool ply) {
    return "scene: room.yaml\n"
           "scanner: {type: rotating, beam_elevations_deg: [-30, 10, -5, 25], "
           "azimuth_resolution_deg: 1, rotation_rate_hz: 10, duration_s: 0.1}\n"
           "platform: {type: static, position_m: [1, 2, 0]}\n"
           "output: {point_format: " +
           std::to_string(point_format) + ", ply: " + (ply ? "true" : "false") +
           ", trajectory_rate_hz: 0}\n";
}

/// The part IDs of the room's planes that `p` lies on (within 2 mm: corners lie on two).
std::set<int> room_parts_at(const test::RawLasPoint& p) {
    std::set<int> ids;
    const auto on = [](double v, double plane) { return std::abs(v - plane) < 2e-3; };
    if (on(p.z, -5))
        ids.insert(1);
    if (on(p.z, 5))
        ids.insert(7);
    if (on(p.x, 10))
        ids.insert(3);
    if (on(p.x, -10))
        ids.insert(4);
    if (on(p.y, 10))
        ids.insert(5);
    if (on(p.y, -10))
        ids.insert(6);
    return ids;
}

/// The LAS scan angle of the beam from (1, 2, 0) to `p` on a static, level platform facing +x:
/// from straight down, positive to the right of travel (-y), +/-90 above the horizontal.
double expected_scan_angle_deg(const test::RawLasPoint& p) {
    const double right = -(p.y - 2.0), down = -p.z;
    if (down <= 0) {
        return right < 0 ? -90.0 : 90.0;
    }
    return std::atan2(right, down) * kRadToDeg;
}

TEST(SurveyOutputs, PointSourceIdIsThePartUserDataTheBeamAndScanAnglesClamp) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", kRoom);
    const test::RawLas las = test::run_survey_raw(room_survey(6, false), dir);
    ASSERT_EQ(las.points.size(), 1440u) << "a closed room returns every pulse";
    std::map<int, std::size_t> per_part;
    std::size_t clamped = 0;
    for (std::size_t i = 0; i < las.points.size(); ++i) {
        const test::RawLasPoint& p = las.points[i];
        // Pulse i is beam i % 4 of firing i / 4, at i / pulse rate.
        ASSERT_EQ(p.user_data, i % 4) << i;
        ASSERT_DOUBLE_EQ(p.gps_time, static_cast<double>(i) / kRoomPulseRate) << i;
        const double horizontal = std::hypot(p.x - 1.0, p.y - 2.0);
        ASSERT_NEAR(std::atan2(p.z, horizontal) * kRadToDeg, kRoomBeamsDeg[p.user_data], 0.05) << i;
        const std::set<int> parts = room_parts_at(p);
        ASSERT_TRUE(parts.count(p.point_source_id) == 1)
            << "point " << i << " (" << p.x << ", " << p.y << ", " << p.z << ") has ID "
            << p.point_source_id;
        ++per_part[p.point_source_id];
        const double want = expected_scan_angle_deg(p);
        if (std::abs(want) == 90.0) {
            ++clamped;
            ASSERT_EQ(std::abs(p.scan_angle_deg()), 90.0) << i;
            if (std::abs(p.y - 2.0) > 0.01) {  // straight ahead or behind: either sign
                ASSERT_EQ(p.scan_angle_deg(), want) << i;
            }
        } else {
            // Half a 0.006 degree step, plus what rounding the point to 1 mm turns the beam by.
            const double quantisation = std::atan2(0.9e-3, std::hypot(p.y - 2.0, p.z));
            ASSERT_NEAR(p.scan_angle_deg(), want, 0.0031 + quantisation * kRadToDeg) << i;
        }
    }
    EXPECT_EQ(clamped, 720u) << "the two upward beams, all clamped to +/-90";
    for (int id : {1, 3, 4, 5, 6, 7}) {
        EXPECT_GT(per_part[id], 0u) << "part " << id;
    }
}

TEST(SurveyOutputs, HeaderRecordsTheSurveyFileSeedAndStandardGpsTime) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", kRoom);
    const std::string yaml = room_survey(6, false);
    const test::RawLas las = test::run_survey_raw(yaml, dir, 42);
    EXPECT_EQ(las.version_major, 1);
    EXPECT_EQ(las.version_minor, 4);
    EXPECT_EQ(las.header_size, 375);
    // LAS 1.4 R15, global encoding: bit 0 = GPS time is adjusted standard GPS time (the docs
    // say so of the survey), bit 4 = WKT, required for point formats 6-10; no waveform bits.
    EXPECT_EQ(las.global_encoding, 0x0011);
    EXPECT_EQ(las.system_identifier, "beamtrace");
    EXPECT_EQ(las.generating_software.rfind("beamtrace ", 0), 0u) << las.generating_software;
    EXPECT_EQ(las.point_format, 6);
    EXPECT_EQ(las.record_length, 30);
    // R15: the legacy 32-bit counts are 0 for point formats 6-10.
    EXPECT_EQ(las.legacy_count, 0u);
    for (auto n : las.legacy_by_return) {
        EXPECT_EQ(n, 0u);
    }
    ASSERT_EQ(las.vlrs.size(), 1u);
    const test::RawLasVlr& vlr = las.vlrs[0];
    EXPECT_EQ(vlr.user_id, "beamtrace");
    EXPECT_EQ(vlr.record_id, 1);
    EXPECT_EQ(vlr.description, "survey file");
    // A first line naming the seed, then the survey file as written.
    const std::size_t eol = vlr.data.find('\n');
    ASSERT_NE(eol, std::string::npos);
    const std::string first = vlr.data.substr(0, eol);
    EXPECT_EQ(first.rfind("# beamtrace ", 0), 0u) << first;
    EXPECT_NE(first.find("seed 42"), std::string::npos) << first;
    EXPECT_EQ(vlr.data.substr(eol + 1), yaml);
}

// ---------------------------------------------------------------------------------------------
// 4. Header bounds and counts by return after a multi-return survey.

// Two planes meeting at x = 0: z = 0 for x < 0, z = -1 for x > 0.
constexpr const char* kStep = R"(parts:
  - {plane: {point_m: [-50, 0, 0], normal: [0, 0, 1], size_m: 100}, label: 2}
  - {plane: {point_m: [50, 0, -1], normal: [0, 0, 1], size_m: 100}, label: 6}
)";

TEST(SurveyOutputs, HeaderBoundsAndReturnCountsAreThoseOfThePoints) {
    test::TempDir dir;
    test::write_file(dir / "step.yaml", kStep);
    // 20 m above the edge, sweeping across it (x) while flying along it (y); a 20 mrad beam of
    // 7 sub-rays (the ring at its cells' centroid, 0.79 x 10 mrad off the axis: 0.158 m at 20 m,
    // six rays 60 degrees apart, reaching 0.137 m across the edge in this frame).
    const test::RawLas las = test::run_survey_raw(R"(scene: step.yaml
scanner: {type: line, pulse_rate_hz: 5000, scan_rate_hz: 50, scan_angle_max_deg: 10, duration_s: 0.5}
platform: {type: legs, speed_mps: 20, waypoints_m: [[0, -10, 20], [0, 10, 20]]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 20, rings: 1}
  atmosphere: {enabled: false}
  waveform: {pulse_fwhm_ns: 2, bin_ns: 0.5}
output: {trajectory_rate_hz: 0}
)",
                                                  dir);
    ASSERT_EQ(las.point_count, las.points.size());
    std::array<std::uint64_t, 15> by_return{};
    std::array<std::int32_t, 3> lo{}, hi{};
    for (std::size_t i = 0; i < las.points.size(); ++i) {
        const auto& p = las.points[i];
        ASSERT_GE(p.return_number, 1);
        ++by_return[static_cast<std::size_t>(p.return_number - 1)];
        const std::int32_t q[3] = {p.ix, p.iy, p.iz};
        for (std::size_t k = 0; k < 3; ++k) {
            lo[k] = i == 0 ? q[k] : std::min(lo[k], q[k]);
            hi[k] = i == 0 ? q[k] : std::max(hi[k], q[k]);
        }
    }
    EXPECT_EQ(las.by_return, by_return);
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(las.min[k], lo[k] * las.scale[k] + las.offset[k]) << "min " << k;
        EXPECT_EQ(las.max[k], hi[k] * las.scale[k] + las.offset[k]) << "max " << k;
    }
    EXPECT_NEAR(las.min[2], -1.0, 0.01);
    EXPECT_NEAR(las.max[2], 0.0, 0.01);
    // The expected returns, from the footprint: every pulse has a first return; a footprint
    // centred within 0.13 m of the edge has rays on both planes (two returns, 1 m apart in
    // range: resolved), one farther than 0.17 m away sees one plane.
    EXPECT_EQ(by_return[0], 2500u) << "one first return per pulse";
    std::size_t near_edge = 0;
    for (std::size_t i = 0; i < las.points.size(); ++i) {
        const auto& p = las.points[i];
        if (p.return_number != 1) {
            continue;
        }
        if (std::abs(p.x) < 0.13) {
            ++near_edge;
            EXPECT_EQ(p.number_of_returns, 2) << "pulse at x = " << p.x;
        } else if (std::abs(p.x) > 0.17) {
            EXPECT_EQ(p.number_of_returns, 1) << "pulse at x = " << p.x;
        }
    }
    EXPECT_GT(near_edge, 20u);
    EXPECT_GE(by_return[1], near_edge);
    EXPECT_EQ(by_return[2], 0u);
}

// ---------------------------------------------------------------------------------------------
// 5. Point formats 7 and 8, and points.ply.

TEST(SurveyOutputs, FormatsSevenAndEightAddTheMaterialColourAndPlyHoldsTheSamePoints) {
    std::map<int, test::RawLas> by_format;
    test::TempDir ply_dir;
    for (int format : {6, 7, 8}) {
        test::TempDir dir;
        test::write_file(dir / "room.yaml", kRoom);
        by_format[format] = test::run_survey_raw(room_survey(format, format == 7), dir);
        if (format == 7) {
            std::filesystem::copy_file(dir / "out" / "points.ply", ply_dir / "points.ply");
        }
    }
    // Record lengths of R15's table: 30 + RGB (6) + NIR (2).
    EXPECT_EQ(by_format[7].record_length, 36);
    EXPECT_EQ(by_format[8].record_length, 38);
    EXPECT_EQ(by_format[7].point_format, 7);
    EXPECT_EQ(by_format[8].point_format, 8);
    const auto& six = by_format[6].points;
    ASSERT_EQ(six.size(), 1440u);
    for (int format : {7, 8}) {
        const auto& pts = by_format[format].points;
        ASSERT_EQ(pts.size(), six.size()) << format;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            // The same points; the default material is white with reflectance 0.5: RGB full
            // scale, NIR half of it (format 8).
            ASSERT_EQ(pts[i].base, six[i].base) << "format " << format << " point " << i;
            ASSERT_EQ(pts[i].rgb, (std::array<std::uint16_t, 3>{65535, 65535, 65535})) << i;
            ASSERT_EQ(pts[i].nir, format == 8 ? 32768 : 0) << i;
        }
    }
    const auto ply = test::parse_points_ply(test::read_file(ply_dir / "points.ply"));
    ASSERT_EQ(ply.size(), six.size());
    std::map<std::int32_t, std::uint16_t> part_of_face;
    for (std::size_t i = 0; i < ply.size(); ++i) {
        const test::PlyVertex& v = ply[i];
        const test::RawLasPoint& p = six[i];
        // The LAS holds the PLY's coordinates rounded to the millimetre.
        ASSERT_NEAR(v.x, p.x, 0.5e-3 + 1e-9) << i;
        ASSERT_NEAR(v.y, p.y, 0.5e-3 + 1e-9) << i;
        ASSERT_NEAR(v.z, p.z, 0.5e-3 + 1e-9) << i;
        ASSERT_EQ(v.ray, i) << "one point per pulse, in pulse order";
        const double range = length(Vec3d{v.x - 1.0, v.y - 2.0, v.z});
        ASSERT_NEAR(v.range, range, 1e-5 * range) << i;
        // Every face belongs to one part.
        const auto [it, fresh] = part_of_face.emplace(v.face_id, p.point_source_id);
        ASSERT_EQ(it->second, p.point_source_id) << "face " << v.face_id;
    }
}

// ---------------------------------------------------------------------------------------------
// 6. waveforms.bin over many pulses.

constexpr const char* kWaveSurvey = R"(scene: floor.yaml
scanner: {type: scan, width: 64, height: 32, hfov_deg: 100, vfov_deg: 60, pulse_rate_hz: 10000}
platform: {type: static, position_m: [0, 0, 10], rotate_deg: [0, -90, 0]}
physics:
  atmosphere: {enabled: false}
  waveform: {pulse_fwhm_ns: 2, bin_ns: 0.25, keep: true}
output: {trajectory_rate_hz: 0}
)";

/// Checks one hit pulse's record: its echo peaks at the sample nearest the round trip 2R/c to
/// the floor along its axis, and every sample k is the Gaussian of the pulse's FWHM centred
/// there, sampled at (first bin + k) x bin size (docs/physics.md), so the echo lies wholly
/// inside the record.
void expect_echo_at_floor_range(const test::WaveRecord& r, double bin_ns, double fwhm_ns) {
    const double range = 10.0 / -r.axis[2];
    const double t_ns = 2.0 * range / kLightMps * 1e9;
    ASSERT_FALSE(r.samples.empty()) << "pulse " << r.pulse;
    const auto peak = std::max_element(r.samples.begin(), r.samples.end());
    const auto at_ns = [&](std::size_t k) {
        return static_cast<double>(r.first_bin + static_cast<std::int64_t>(k)) * bin_ns;
    };
    const double peak_ns = at_ns(static_cast<std::size_t>(peak - r.samples.begin()));
    EXPECT_LE(std::abs(peak_ns - t_ns), bin_ns / 2 + 1e-6) << "pulse " << r.pulse;
    const double sigma_ns = fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    const auto gauss = [&](double t) {
        return std::exp(-(t - t_ns) * (t - t_ns) / (2.0 * sigma_ns * sigma_ns));
    };
    const double amplitude = *peak / gauss(peak_ns);
    for (std::size_t k = 0; k < r.samples.size(); ++k) {
        ASSERT_NEAR(r.samples[k], amplitude * gauss(at_ns(k)), 0.01 * amplitude)
            << "pulse " << r.pulse << " sample " << k;
    }
    EXPECT_LT(r.samples.front(), 0.01f * *peak) << "pulse " << r.pulse;
    EXPECT_LT(r.samples.back(), 0.01f * *peak) << "pulse " << r.pulse;
}

TEST(SurveyOutputs, WaveformsHoldEveryPulseWithItsEchoAtTheRoundTripTime) {
    test::TempDir dir;
    test::write_file(dir / "floor.yaml",
                     "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 16}\n");
    // 2048 pulses (two blocks of 1024) from 10 m above a 16 m floor; the outer columns miss it.
    const test::RawLas las = test::run_survey_raw(kWaveSurvey, dir, 1, 1, 1024);
    const std::string bytes = test::read_file(dir / "out" / "waveforms.bin");
    const test::WaveFile w = test::parse_waveforms(bytes);
    EXPECT_EQ(w.bin_ns, 0.25);
    EXPECT_EQ(w.fwhm_ns, 2.0);
    ASSERT_EQ(w.records.size(), 2048u);
    EXPECT_EQ(w.bytes_read, bytes.size()) << "records back to back up to the end";
    std::size_t hits = 0, misses = 0;
    for (std::size_t i = 0; i < w.records.size(); ++i) {
        const test::WaveRecord& r = w.records[i];
        ASSERT_EQ(r.pulse, i);
        ASSERT_DOUBLE_EQ(r.gps_time, static_cast<double>(i) / 10000.0);
        ASSERT_EQ(r.origin, (std::array<double, 3>{0, 0, 10}));
        ASSERT_NEAR(std::hypot(r.axis[0], r.axis[1], r.axis[2]), 1.0, 1e-12);
        ASSERT_LT(r.axis[2], 0.0) << "looking down";
        const double range = 10.0 / -r.axis[2];
        const double fx = range * r.axis[0], fy = range * r.axis[1];
        const double margin = 8.0 - std::max(std::abs(fx), std::abs(fy));
        if (std::abs(margin) < 0.01) {
            continue;  // at the floor's edge: hit or miss
        }
        if (margin < 0) {
            ++misses;
            EXPECT_TRUE(r.samples.empty()) << "a miss has no samples, pulse " << i;
            EXPECT_EQ(r.first_bin, 0) << "a miss has no first bin, pulse " << i;
            continue;
        }
        ++hits;
        expect_echo_at_floor_range(r, w.bin_ns, w.fwhm_ns);
        // The LAS point of a hit pulse (pulse order) lies on the record's axis at that range.
        const auto p = std::find_if(las.points.begin(), las.points.end(),
                                    [&](const auto& q) { return q.gps_time == r.gps_time; });
        ASSERT_NE(p, las.points.end()) << "pulse " << i;
        EXPECT_NEAR(p->x, fx, 1e-3);
        EXPECT_NEAR(p->y, fy, 1e-3);
        EXPECT_NEAR(p->z, 0.0, 1e-3);
    }
    EXPECT_GT(hits, 1000u);
    EXPECT_GT(misses, 100u);
}

TEST(SurveyOutputs, WaveformsAreTheSameBytesForAnyThreadCount) {
    // A floor under one half of the field only (each side in turn): one of the two blocks of
    // 1024 pulses ends on hits and the other starts on misses, so a value a miss's record kept
    // from a previously simulated pulse would depend on which thread took which block.
    for (const char* y : {"20", "-20"}) {
        test::TempDir a, b;
        for (const test::TempDir* dir : {&a, &b}) {
            test::write_file(*dir / "floor.yaml", std::string("parts:\n  - plane: {point_m: [0, ") +
                                                      y + ", 0], normal: [0, 0, 1], size_m: 40}\n");
        }
        (void)test::run_survey_raw(kWaveSurvey, a, 1, 1, 1024);
        (void)test::run_survey_raw(kWaveSurvey, b, 1, 2, 2048);
        EXPECT_EQ(test::read_file(a / "out" / "waveforms.bin"),
                  test::read_file(b / "out" / "waveforms.bin"))
            << "floor at y " << y;
    }
}

}  // namespace
}  // namespace beamtrace
