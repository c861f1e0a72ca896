// output.extra_bytes (docs/survey.md): range, incidence angle, echo width, beam and object ID as
// LAS 1.4 extra bytes with an Extra Bytes VLR, checked against the geometry of a tilted plane
// at a known range and incidence, read back by our reader and by the independent npm readers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_extra_bytes.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "io/independent_las.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kTiltDeg = 30.0;  ///< the plane's normal from the vertical
constexpr double kDepthM = 40.0;   ///< the plane passes 40 m below the scanner
constexpr int kPartId = 7;
constexpr const char* kAll = "[range, incidence_angle, echo_width, beam, object_id]";

/// The plane's unit normal.
Vec3d plane_normal() {
    const double t = kTiltDeg * std::numbers::pi / 180.0;
    return {std::sin(t), 0.0, std::cos(t)};
}

/// A 3 x 3 pinhole looking straight down from the origin onto the tilted plane (its centre
/// pixel's ray meets it 40 m away at 30 degrees), `output` and `physics` as given.
std::string tilted_survey(const std::string& output, const std::string& physics) {
    return "scene: plane.yaml\n"
           "scanner: {type: pinhole, width: 3, height: 3, hfov_deg: 4, vfov_deg: 4}\n"
           "platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, -90, 0]}\n" +
           physics + "output: {trajectory_rate_hz: 0" + output + "}\n";
}

const std::string kPhysics =
    "physics:\n  atmosphere: {enabled: false}\n  waveform: {pulse_fwhm_ns: 5}\n";

void write_scene(const test::TempDir& dir) {
    const Vec3d n = plane_normal();
    test::write_file(dir / "plane.yaml",
                     "materials: [{name: white, reflectance: 1}]\n"
                     "parts: [{plane: {point_m: [0, 0, -40], normal: [" +
                         std::to_string(n.x) + ", 0, " + std::to_string(n.z) +
                         "], size_m: 200}, material: white, part_id: 7}]\n");
}

struct Read {
    LasHeader header;
    std::vector<LasExtraBytesDescriptor> fields;
    std::vector<LasPoint> points;
};

Read read_back(const std::filesystem::path& file) {
    LasReader reader(file);
    Read r{reader.header(), las_extra_bytes_descriptors(reader.vlrs()), {}};
    r.points = read_las_points(file);
    return r;
}

/// Field `i` of point `p` as the descriptors say.
double value(const Read& r, std::size_t i, const LasPoint& p) {
    return las_extra_bytes_value(r.fields, i, p.extra_bytes);
}

TEST(SurveyExtraBytes, DescriptorsNameTypeAndScaleEveryAttribute) {
    test::TempDir dir;
    write_scene(dir);
    test::run_survey_in(tilted_survey(std::string(", extra_bytes: ") + kAll, kPhysics), dir, 2,
                        1 << 16, 1);
    const Read r = read_back(dir / "out" / "points.las");
    ASSERT_EQ(r.fields.size(), 5u);
    const char* names[] = {"range_m", "incidence_angle_deg", "echo_width_ns", "beam", "object_id"};
    const LasExtraType types[] = {LasExtraType::u32, LasExtraType::u16, LasExtraType::u16,
                                  LasExtraType::u16, LasExtraType::u32};
    const double scales[] = {0.001, 0.01, 0.01, 1.0, 1.0};
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_EQ(r.fields[i].name, names[i]);
        EXPECT_EQ(r.fields[i].data_type, types[i]) << names[i];
        const bool scaled = (r.fields[i].options & LasExtraBytesDescriptor::kScale) != 0;
        EXPECT_EQ(scaled, scales[i] != 1.0) << names[i];
        if (scaled) {
            EXPECT_EQ(r.fields[i].scale, scales[i]) << names[i];
        }
        EXPECT_FALSE(r.fields[i].description.empty()) << names[i];
    }
    // echo_width_ns alone has a no-data value: its type's largest.
    EXPECT_EQ(r.fields[2].options & LasExtraBytesDescriptor::kNoData,
              LasExtraBytesDescriptor::kNoData);
    EXPECT_EQ(r.fields[2].no_data, 65535.0);
    EXPECT_EQ(r.header.point_record_length, 30 + 14);
    // beamtrace info lists them under the VLR.
    const auto info = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " info '" +
                                        (dir / "out" / "points.las").string() + "'");
    EXPECT_EQ(info.exit_code, 0) << info.out;
    for (const char* line : {"    range_m: uint32 x 0.001  \"range from beam origin, m\"\n",
                             "    echo_width_ns: uint16 x 0.01, no data 65535  \"echo FWHM, ns\"\n",
                             "    object_id: uint32  \"scene part_id of the hit\"\n"}) {
        EXPECT_NE(info.out.find(line), std::string::npos) << line << info.out;
    }
}

/// Every value of every point against the plane: range = |xyz| (the scanner is at the origin),
/// incidence = the angle of xyz to the normal, beam = the pixel row, object_id = the part ID.
void expect_geometry(const Read& r, bool physics) {
    ASSERT_EQ(r.points.size(), 9u);
    const Vec3d n = plane_normal();
    for (std::size_t i = 0; i < r.points.size(); ++i) {
        SCOPED_TRACE("point " + std::to_string(i));
        const LasPoint& p = r.points[i];
        const Vec3d xyz{p.x, p.y, p.z};
        ASSERT_NEAR(dot(n, xyz), -kDepthM * n.z, 2e-3) << "on the plane";
        // Coordinates are quantised to 1 mm per axis; the range to 1 mm.
        EXPECT_NEAR(value(r, 0, p), length(xyz), 2e-3);
        const double incidence =
            std::acos(std::abs(dot(n, xyz)) / length(xyz)) * 180.0 / std::numbers::pi;
        EXPECT_NEAR(value(r, 1, p), incidence, 0.011);
        if (physics) {
            EXPECT_NEAR(value(r, 2, p), 5.0, 0.15) << "a flat target keeps the pulse's FWHM";
        } else {
            // The raw value is the descriptor's no-data value.
            EXPECT_NEAR(value(r, 2, p) / r.fields[2].scale, r.fields[2].no_data, 1e-6)
                << "no physics: the no-data value";
        }
        EXPECT_EQ(value(r, 3, p), static_cast<double>(i % 3)) << "the pinhole's row (column-major)";
        EXPECT_EQ(value(r, 3, p), p.user_data);
        EXPECT_EQ(value(r, 4, p), kPartId);
        EXPECT_EQ(p.point_source_id, kPartId);
    }
    // The centre pixel's ray is the platform's axis: 40 m at 30 degrees exactly.
    EXPECT_NEAR(value(r, 0, r.points[4]), kDepthM, 1e-3);
    EXPECT_NEAR(value(r, 1, r.points[4]), kTiltDeg, 0.006);
}

TEST(SurveyExtraBytes, ValuesEqualTheGeometryWithPhysics) {
    test::TempDir dir;
    write_scene(dir);
    test::run_survey_in(tilted_survey(std::string(", laz: true, extra_bytes: ") + kAll, kPhysics),
                        dir, 2, 1 << 16, 1);
    const Read las = read_back(dir / "out" / "points.las");
    expect_geometry(las, true);
    // points.laz holds the same extra bytes.
    const Read laz = read_back(dir / "out" / "points.laz");
    ASSERT_EQ(laz.points.size(), las.points.size());
    EXPECT_EQ(laz.fields.size(), 5u);
    for (std::size_t i = 0; i < las.points.size(); ++i) {
        EXPECT_EQ(laz.points[i].extra_bytes, las.points[i].extra_bytes) << "point " << i;
    }
}

TEST(SurveyExtraBytes, FollowTheWavePacketsOfFormat9) {
    test::TempDir dir;
    write_scene(dir);
    test::run_survey_in(tilted_survey(std::string(", extra_bytes: ") + kAll,
                                      "physics:\n  atmosphere: {enabled: false}\n"
                                      "  waveform: {pulse_fwhm_ns: 5, keep: true}\n"),
                        dir, 2, 1 << 16, 1);
    const Read r = read_back(dir / "out" / "points.las");
    EXPECT_EQ(r.header.point_format, 9);
    EXPECT_EQ(r.header.point_record_length, 30 + 29 + 14);
    expect_geometry(r, true);
    for (const LasPoint& p : r.points) {
        EXPECT_NE(p.wave_descriptor_index, 0) << "the wave packet fields are kept";
        EXPECT_GT(p.wave_packet_size, 0u);
    }
}

TEST(SurveyExtraBytes, DivergentBeamAtNormalIncidenceKeepsThePulseWidth) {
    test::TempDir dir;
    test::write_file(dir / "plane.yaml", R"(materials: [{name: white, reflectance: 1}]
parts: [{plane: {point_m: [0, 0, -40], normal: [0, 0, 1], size_m: 200}, material: white}]
)");
    // A 2 mrad beam of sub-rays: the dominant sub-ray is at most 1 mrad (0.057 deg) off normal.
    test::run_survey_in(
        "scene: plane.yaml\n"
        "scanner: {type: pinhole, width: 1, height: 1, hfov_deg: 1, vfov_deg: 1}\n"
        "platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, -90, 0]}\n"
        "physics:\n  atmosphere: {enabled: false}\n  beam: {divergence_mrad: 2}\n"
        "  waveform: {pulse_fwhm_ns: 5}\n"
        "output: {trajectory_rate_hz: 0, extra_bytes: [incidence_angle, echo_width]}\n",
        dir, 1, 1 << 16, 1);
    const Read r = read_back(dir / "out" / "points.las");
    ASSERT_EQ(r.points.size(), 1u);
    EXPECT_NEAR(value(r, 0, r.points[0]), 0.0, 0.06);
    EXPECT_NEAR(value(r, 1, r.points[0]), 5.0, 0.15) << "a flat target keeps the pulse's FWHM";
}

TEST(SurveyExtraBytes, ValuesEqualTheGeometryWithoutPhysics) {
    test::TempDir dir;
    write_scene(dir);
    test::run_survey_in(tilted_survey(std::string(", extra_bytes: ") + kAll, ""), dir, 2, 1 << 16,
                        1);
    expect_geometry(read_back(dir / "out" / "points.las"), false);
}

TEST(SurveyExtraBytes, OrderAndSubsetFollowTheList) {
    test::TempDir dir;
    write_scene(dir);
    test::run_survey_in(tilted_survey(", extra_bytes: [object_id, range]", kPhysics), dir, 2,
                        1 << 16, 1);
    const Read r = read_back(dir / "out" / "points.las");
    ASSERT_EQ(r.fields.size(), 2u);
    EXPECT_EQ(r.fields[0].name, "object_id");
    EXPECT_EQ(r.fields[1].name, "range_m");
    EXPECT_EQ(r.header.point_record_length, 30 + 8);
    ASSERT_EQ(r.points.size(), 9u);
    EXPECT_EQ(value(r, 0, r.points[4]), kPartId);
    EXPECT_NEAR(value(r, 1, r.points[4]), kDepthM, 1e-3);
}

TEST(SurveyExtraBytes, WithoutTheKeyTheRecordsAreThePointFormatAlone) {
    test::TempDir with, without;
    write_scene(with);
    write_scene(without);
    test::run_survey_in(tilted_survey(std::string(", extra_bytes: ") + kAll, kPhysics), with, 2,
                        1 << 16, 1);
    test::run_survey_in(tilted_survey("", kPhysics), without, 2, 1 << 16, 1);
    const Read a = read_back(with / "out" / "points.las");
    const Read b = read_back(without / "out" / "points.las");
    EXPECT_TRUE(b.fields.empty()) << "no Extra Bytes VLR";
    EXPECT_EQ(b.header.point_record_length, 30);
    const LasReader plain(without / "out" / "points.las");
    for (const LasVlr& v : plain.vlrs()) {
        EXPECT_FALSE(v.user_id == "LASF_Spec" && v.record_id == 4);
    }
    ASSERT_EQ(a.points.size(), b.points.size());
    for (std::size_t i = 0; i < a.points.size(); ++i) {
        EXPECT_TRUE(b.points[i].extra_bytes.empty());
        EXPECT_EQ(a.points[i].x, b.points[i].x);
        EXPECT_EQ(a.points[i].z, b.points[i].z);
        EXPECT_EQ(a.points[i].intensity, b.points[i].intensity);
        EXPECT_EQ(a.points[i].gps_time, b.points[i].gps_time);
    }
}

TEST(SurveyExtraBytes, IndependentReadersNameAndDecodeThem) {
    BEAMTRACE_REQUIRE_LASVAL(lasval);
    test::TempDir dir;
    write_scene(dir);
    test::run_survey_in(tilted_survey(std::string(", extra_bytes: ") + kAll, kPhysics), dir, 2,
                        1 << 16, 1);
    const Read r = read_back(dir / "out" / "points.las");
    const auto decoded = test::decode_independently(lasval, dir / "out" / "points.las", dir.path());
    ASSERT_TRUE(decoded);
    ASSERT_EQ(decoded->count, r.points.size());
    for (std::size_t f = 0; f < r.fields.size(); ++f) {
        const int k = decoded->dim(r.fields[f].name);
        ASSERT_GE(k, 0) << "copc.js has no dimension " << r.fields[f].name;
        for (std::size_t i = 0; i < r.points.size(); ++i) {
            EXPECT_NEAR(decoded->at(i, static_cast<std::size_t>(k)), value(r, f, r.points[i]), 1e-9)
                << r.fields[f].name << " of point " << i;
        }
    }
    // And against the geometry, from copc.js's own X, Y, Z: the centre pixel 40 m away at 30
    // degrees, every range |xyz|.
    const auto at = [&](std::size_t i, const char* dim) {
        return decoded->at(i, static_cast<std::size_t>(decoded->dim(dim)));
    };
    for (std::size_t i = 0; i < decoded->count; ++i) {
        const Vec3d xyz{at(i, "X"), at(i, "Y"), at(i, "Z")};
        EXPECT_NEAR(at(i, "range_m"), length(xyz), 2e-3) << "point " << i;
        EXPECT_NEAR(at(i, "echo_width_ns"), 5.0, 0.15) << "point " << i;
        EXPECT_EQ(at(i, "object_id"), kPartId);
    }
    EXPECT_NEAR(at(4, "range_m"), kDepthM, 1e-3);
    EXPECT_NEAR(at(4, "incidence_angle_deg"), kTiltDeg, 0.006);
}

/// The error of a survey whose output block is `output` (one line, or "" when it loads).
std::string error_of(const std::string& output) {
    test::TempDir dir;
    write_scene(dir);
    test::write_file(dir / "survey.yaml", tilted_survey(output, ""));
    try {
        (void)load_survey_spec(dir / "survey.yaml");
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

TEST(SurveyExtraBytes, BadListsGiveOneLineErrors) {
    struct Case {
        std::string output, expected;
    };
    const Case cases[] = {
        {", extra_bytes: [range, speed]",
         "survey.yaml:4: output.extra_bytes: unknown name 'speed'; expected one of range, "
         "incidence_angle, echo_width, beam, object_id"},
        {", extra_bytes: [beam, range, beam]",
         "survey.yaml:4: output.extra_bytes: 'beam' is listed twice"},
        {", extra_bytes: range", "survey.yaml:4: output.extra_bytes: expected a list of names"},
        {", extra_bytes: [[range]]", "survey.yaml:4: output.extra_bytes: not a name"},
    };
    for (const Case& c : cases) {
        const std::string e = error_of(c.output);
        EXPECT_NE(e.find(c.expected), std::string::npos) << c.output << "\n" << e;
        EXPECT_EQ(e.find('\n', e.find("output.extra_bytes")), std::string::npos) << e;
    }
    EXPECT_EQ(error_of(", extra_bytes: []"), "");
}

}  // namespace
}  // namespace beamtrace
