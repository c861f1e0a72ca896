// Survey files that used to escape parse_survey_spec as yaml-cpp or filesystem exceptions
// (issue 15, findings 1, 2, 3, 8): each is a ConfigError naming the file, line and key.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

const std::string kBase =
    "scene: demo\n"
    "scanner: {type: rotating, preset: vlp16, duration_s: 0.01}\n"
    "platform: {type: static, position_m: [0, 0, 0]}\n";

/// The ConfigError message of parsing kBase + `extra` as `source`; fails on any other outcome.
std::string config_error(const std::string& yaml, const std::filesystem::path& source = "s.yaml") {
    try {
        (void)parse_survey_spec(yaml, source);
    } catch (const ConfigError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not a ConfigError: " << e.what();
        return {};
    }
    ADD_FAILURE() << "accepted";
    return {};
}

TEST(SurveyYamlHostile, ListsAndMapsAsKeysAreConfigErrors) {
    for (const char* extra :
         {"[a]: 1\n", "? {b: 1}\n: 2\n", "output: {[las]: true}\n", "mount: {[x]: 1}\n",
          "physics: {[x]: 1}\n", "physics: {noise: {[x]: 1}}\n"}) {
        SCOPED_TRACE(extra);
        const std::string msg = config_error(kBase + extra);
        EXPECT_EQ(msg.rfind("s.yaml:4: ", 0), 0u) << msg;
        EXPECT_NE(msg.find("a key must be a name"), std::string::npos) << msg;
    }
    const std::string msg =
        config_error("scene: demo\nscanner: {type: line, [k]: 1}\nplatform: {type: static}\n");
    EXPECT_NE(msg.find("s.yaml:2: scanner: a key must be a name, not a list"), std::string::npos)
        << msg;
    const std::string msg2 = config_error(kBase + "mount: {{k: 1}: 1}\n");
    EXPECT_NE(msg2.find("a key must be a name, not a map"), std::string::npos) << msg2;
}

TEST(SurveyYamlHostile, MountAndOutputMustBeMaps) {
    for (const auto& [extra, expected] :
         {std::pair{"mount: 5\n", "s.yaml:4: mount: expected a map"},
          std::pair{"mount: [1, 2, 3]\n", "s.yaml:4: mount: expected a map"},
          std::pair{"mount: lever\n", "s.yaml:4: mount: expected a map"},
          std::pair{"output: 7\n", "s.yaml:4: output: expected a map"},
          std::pair{"output: [csv, las]\n", "s.yaml:4: output: expected a map"}}) {
        SCOPED_TRACE(extra);
        const std::string msg = config_error(kBase + std::string(extra));
        EXPECT_EQ(msg.rfind(expected, 0), 0u) << msg;
    }
}

TEST(SurveyYamlHostile, EmptyMountAndOutputBlocksKeepTheDefaults) {
    const SurveySpec s = parse_survey_spec(kBase + "mount:\noutput:\n", "s.yaml");
    EXPECT_EQ(s.point_format, SurveySpec{}.point_format);
}

TEST(SurveyYamlHostile, NamesTheFileSystemRefusesAreConfigErrors) {
    test::TempDir dir;
    std::filesystem::create_symlink("loop", dir / "loop");
    const std::string scanner = "scanner: {type: line, duration_s: 0.1}\n";
    const std::string msg_long = config_error(
        "scene: " + std::string(300, 's') + ".yaml\n" + scanner + "platform: {type: static}\n",
        dir / "s.yaml");
    EXPECT_NE(msg_long.find("s.yaml:1: scene: cannot check the file '" + std::string(80, 's') +
                            "...': File name too long"),
              std::string::npos)
        << msg_long;
    const std::string msg_loop = config_error(
        "scene: demo\n" + scanner + "platform: {type: trajectory, file: loop/poses.csv}\n",
        dir / "s.yaml");
    EXPECT_NE(msg_loop.find("s.yaml:3: platform.file: cannot check the file " +
                            (dir / "loop/poses.csv").string()),
              std::string::npos)
        << msg_loop;
}

TEST(SurveyYamlHostile, LongValuesAreQuotedClipped) {
    const std::string big(std::size_t{1} << 20, 'w');
    for (const std::string& yaml : std::vector<std::string>{
             kBase + "? " + big + "\n: 1\n", kBase + "output:\n  ? " + big + "\n  : true\n",
             kBase + "output:\n  trajectory_rate_hz: " + big + "\n",
             kBase + "physics:\n  returns:\n    mode: " + big + "\n",
             kBase + "physics:\n  intensity:\n    scale: " + big + "\n",
             "scene: demo\nscanner:\n  type: line\n  waveform: " + big +
                 "\nplatform: {type: static}\n",
             "scene: demo\nscanner:\n  type: line\n  ? " + big +
                 "\n  : 1\nplatform: {type: static}\n"}) {
        const std::string msg = config_error(yaml);
        EXPECT_LT(msg.size(), 400u) << msg.substr(0, 400);
        EXPECT_NE(msg.find(std::string(80, 'w') + "..."), std::string::npos) << msg.substr(0, 400);
    }
}

}  // namespace
}  // namespace beamtrace
