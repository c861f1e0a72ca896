// Every example survey, run through the CLI, decoded by two independent LAS readers (copc.js
// and loaders.gl's laz-rs, npm packages) and compared point by point with the survey's own CSV
// (written from the same points before LAS quantisation, in shortest round-trip decimals).
#include <gtest/gtest.h>

#include <algorithm>

#include <charconv>
#include <filesystem>
#include <string>
#include <vector>

#include "beamtrace/io/las.hpp"
#include "io/independent_las.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// A copy of example survey `name` in `dir` that also writes points.csv, its scene path made
/// absolute (the original's is relative to examples/surveys).
fs::path with_csv_output(const std::string& name, const fs::path& dir) {
    const fs::path source = fs::path(BEAMTRACE_EXAMPLES_DIR) / "surveys" / name;
    std::string text = test::read_file(source);
    const std::string scene_key = "\nscene: ";
    if (const auto at = text.find(scene_key); at != std::string::npos) {
        const auto value = at + scene_key.size();
        if (text.compare(value, 4, "demo") != 0) {
            text.insert(value, source.parent_path().string() + "/");
        }
    } else if (text.rfind("scene: ", 0) == 0 && text.compare(7, 4, "demo") != 0) {
        text.insert(7, source.parent_path().string() + "/");
    }
    if (const auto at = text.find("\noutput:\n"); at != std::string::npos) {
        if (text.find("\n  csv: true") == std::string::npos) {
            text.insert(at + 9, "  csv: true\n");
        }
    } else {
        text += "\noutput:\n  csv: true\n";
    }
    return test::write_file(dir / name, text);
}

/// The points of a survey's points.csv as LAS points: user data = beam, and without physics
/// columns return 1 of 1 with intensity 0 (docs/survey.md).
std::vector<LasPoint> read_survey_csv(const fs::path& path) {
    const std::string text = test::read_file(path);
    const auto first_newline = text.find('\n');
    const std::string header = text.substr(0, first_newline);
    const bool physics =
        header.find(",intensity,return_number,number_of_returns") != std::string::npos;
    // Surveys with `scanners:`: the LAS scanner channel, the last column.
    const std::string channel_column = ",scanner_channel";
    const bool channel = header.size() >= channel_column.size() &&
                         header.compare(header.size() - channel_column.size(),
                                        channel_column.size(), channel_column) == 0;
    EXPECT_EQ(header.rfind("x,y,z,gps_time,range_m,classification,point_source_id,beam,"
                           "scan_angle_deg",
                           0),
              0u)
        << header;
    std::vector<LasPoint> points;
    const char* c = text.data() + first_newline + 1;
    const char* const end = text.data() + text.size();
    while (c < end) {
        double v[12] = {};
        const int columns = physics ? 12 : 9;
        for (int k = 0; k < columns; ++k) {
            const auto r = std::from_chars(c, end, v[k]);
            if (r.ec != std::errc{}) {
                ADD_FAILURE() << path << ": bad CSV value at row " << points.size() + 1;
                return points;
            }
            c = r.ptr + 1;  // past ',' or '\n'
        }
        unsigned scanner_channel = 0;
        if (c[-1] == ',') {  // output.extra_bytes columns follow: not read here
            const char* eol = std::find(c, end, '\n');
            if (channel) {  // but the last, the scanner channel, is
                const char* last = eol;
                while (last[-1] != ',') {
                    --last;
                }
                (void)std::from_chars(last, eol, scanner_channel);
            }
            c = eol == end ? end : eol + 1;
        }
        LasPoint p;
        p.x = v[0], p.y = v[1], p.z = v[2], p.gps_time = v[3];
        p.classification = static_cast<std::uint8_t>(v[5]);
        p.point_source_id = static_cast<std::uint16_t>(v[6]);
        p.user_data = static_cast<std::uint8_t>(static_cast<unsigned>(v[7]) & 0xFFu);
        p.scan_angle_deg = static_cast<float>(v[8]);
        p.intensity = physics ? static_cast<std::uint16_t>(v[9]) : 0;
        p.return_number = physics ? static_cast<std::uint8_t>(v[10]) : 1;
        p.number_of_returns = physics ? static_cast<std::uint8_t>(v[11]) : 1;
        p.scanner_channel = static_cast<std::uint8_t>(scanner_channel);
        points.push_back(p);
    }
    return points;
}

/// Every example survey but airborne_srtm_1e8.yaml (10^8 points, a 3 GB file: a benchmark; it is
/// airborne_srtm.yaml at 5x the pulse rate). Under the sanitizers, the surveys of the demo scene
/// only (the SRTM ones take minutes there and run the same code).
std::vector<std::string> example_surveys() {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(fs::path(BEAMTRACE_EXAMPLES_DIR) / "surveys")) {
        const std::string name = e.path().filename().string();
        if (e.path().extension() != ".yaml" || name == "airborne_srtm_1e8.yaml") {
            continue;
        }
#ifdef BEAMTRACE_SANITIZED
        if (name.rfind("airborne_srtm", 0) == 0) {
            continue;
        }
#endif
        names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    return names;
}

TEST(SurveyExamples, IndependentReadersDecodeExactlyThePointsOfEveryExample) {
    BEAMTRACE_REQUIRE_LASVAL(lasval);
    const auto names = example_surveys();
#ifdef BEAMTRACE_SANITIZED
    EXPECT_GE(names.size(), 5u);
#else
    EXPECT_GE(names.size(), 7u);
#endif
    for (const auto& name : names) {
        SCOPED_TRACE(name);
        test::TempDir dir;
        const fs::path survey = with_csv_output(name, dir.path());
        const auto r =
            test::run_command(std::string(BEAMTRACE_CLI_PATH) + " survey '" + survey.string() +
                              "' --quiet --output '" + (dir / "out").string() + "'");
        ASSERT_EQ(r.exit_code, 0) << r.out;
        const std::vector<LasPoint> written = read_survey_csv(dir / "out" / "points.csv");
        EXPECT_GT(written.size(), 10000u);
        const auto decoded =
            test::decode_independently(lasval, dir / "out" / "points.las", dir.path());
        ASSERT_TRUE(decoded);
        // Surveys write point format 6 at 1 mm, no flags (docs/survey.md).
        test::expect_decodes_as(*decoded, written, {6, {0.001, 0.001, 0.001}, std::nullopt}, name);
        const Vec3d offset = decoded->header_vec("offset");
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(offset[a], std::round(offset[a])) << "offset is the scene's rounded centre";
        }
        EXPECT_EQ(decoded->facts.at("systemIdentifier"), "beamtrace");
        EXPECT_EQ(decoded->facts.at("generatingSoftware").get<std::string>().rfind("beamtrace ", 0),
                  0u);
        EXPECT_EQ(decoded->facts.at("globalEncoding").get<int>() & 1, 1)
            << "GPS times are adjusted standard GPS time";
    }
}

}  // namespace
}  // namespace beamtrace
