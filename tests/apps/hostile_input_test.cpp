// Hostile and careless config input fed to the CLI (issue 15, findings 1, 2, 3, 5, 8): YAML
// keys that are lists, blocks that are not maps, path names the file system refuses, copy
// counts and files too large, values too long to quote, devices given as files. Each one exits
// 2 with one line naming the file at fault, never an internal error, writes nothing, and stays
// under 100 MB of memory.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "heightfield/child_peak_rss.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

constexpr const char* kScanner =
    "scanner: {type: rotating, preset: vlp16, duration_s: 0.01}\n"
    "platform: {type: static, position_m: [0, 0, 0]}\n";

constexpr const char* kFloor =
    "parts:\n  - plane: {point_m: [0, 0, -2], normal: [0, 0, 1], size_m: 40}\n";

/// The peak memory allowed while refusing any of these inputs.
constexpr std::size_t kPeakLimitBytes = std::size_t{100} << 20;

/// One reproducer: `setup` writes its files into `dir` and returns the CLI's arguments after
/// the program (with the output folder `out`); `fragment` (a path in `dir` or absolute, found
/// by `name`) is expected in the message.
struct Hostile {
    const char* name;
    std::function<std::vector<std::string>(const fs::path& dir, const fs::path& out)> setup;
    std::function<std::string(const fs::path& dir)> fragment;
};

std::vector<std::string> survey_args(const fs::path& survey, const fs::path& out) {
    return {"survey", survey.string(), "--quiet", "--output", out.string()};
}

/// A survey.yaml of `survey_text` beside a scene.yaml of `scene_text`.
Hostile survey_case(const char* name, std::string survey_text, std::string scene_text,
                    const char* fault_file) {
    return {name,
            [survey_text, scene_text](const fs::path& dir, const fs::path& out) {
                test::write_file(dir / "scene.yaml", scene_text);
                test::write_file(dir / "survey.yaml", survey_text);
                return survey_args(dir / "survey.yaml", out);
            },
            [fault_file](const fs::path& dir) { return (dir / fault_file).string() + ":"; }};
}

/// A survey naming /dev/zero as its `kind` ("scene") file.
Hostile dev_zero_case(const char* name, std::string survey_text, const std::string& kind) {
    Hostile h = survey_case(name, std::move(survey_text), kFloor, "survey.yaml");
    h.fragment = [kind](const fs::path&) {
        return "/dev/zero: the " + kind + " file is not a regular file";
    };
    return h;
}

std::string scene_with(const std::string& part) {
    return "parts:\n  - " + part + "\n";
}

std::string survey_with(const std::string& extra) {
    return "scene: scene.yaml\n" + std::string(kScanner) + extra;
}

std::vector<Hostile> hostile_inputs() {
    const std::string plane = "plane: {point_m: [0, 0, -2], normal: [0, 0, 1], size_m: 40}";
    const std::string long_name(300, 'n');
    std::vector<Hostile> cases = {
        // Finding 1: a list or a map as a key.
        survey_case("list key at the top", survey_with("[a]: 1\n"), kFloor, "survey.yaml"),
        survey_case("map key in scanner",
                    "scene: scene.yaml\nscanner: {type: line, {a: 1}: 2}\n"
                    "platform: {type: static}\n",
                    kFloor, "survey.yaml"),
        survey_case("list key in output", survey_with("output: {[csv]: true}\n"), kFloor,
                    "survey.yaml"),
        survey_case("list key in mount", survey_with("mount: {[x]: 1}\n"), kFloor, "survey.yaml"),
        survey_case("list key in physics", survey_with("physics: {beam: {[x]: 1}}\n"), kFloor,
                    "survey.yaml"),
        survey_case("list key in a part", survey_with(""), scene_with("{[a]: 1, " + plane + "}"),
                    "scene.yaml"),
        survey_case("list key in a material", survey_with(""),
                    "materials:\n  - {name: m, [a]: 1}\n" + std::string(kFloor), "scene.yaml"),
        // Finding 2: mount and output not maps.
        survey_case("mount a number", survey_with("mount: 5\n"), kFloor, "survey.yaml"),
        survey_case("mount a list", survey_with("mount: [1, 2, 3]\n"), kFloor, "survey.yaml"),
        survey_case("output a number", survey_with("output: 7\n"), kFloor, "survey.yaml"),
        survey_case("output a list", survey_with("output: [csv, las]\n"), kFloor, "survey.yaml"),
        // Finding 3: names the file system refuses to look up.
        survey_case("scene name too long", "scene: " + long_name + ".yaml\n" + kScanner, kFloor,
                    "survey.yaml"),
        survey_case("trajectory name too long",
                    "scene: scene.yaml\nscanner: {type: line, duration_s: 0.1}\n"
                    "platform: {type: trajectory, file: " +
                        long_name + ".csv}\n",
                    kFloor, "survey.yaml"),
        survey_case("mesh name too long", survey_with(""),
                    scene_with("mesh: " + long_name + ".obj"), "scene.yaml"),
        {"scene behind a loop of links",
         [](const fs::path& dir, const fs::path& out) {
             fs::create_symlink("loop", dir / "loop");
             test::write_file(dir / "survey.yaml",
                              "scene: loop/scene.yaml\n" + std::string(kScanner));
             return survey_args(dir / "survey.yaml", out);
         },
         [](const fs::path& dir) { return (dir / "survey.yaml").string() + ":1: scene"; }},
        // Finding 5: copies of a part.
        survey_case("10^8 copies of a part", survey_with(""),
                    scene_with(plane + "\n    array: {count: [10000, 10000, 1]}"), "scene.yaml"),
        survey_case("10^6 copies per axis", survey_with(""),
                    scene_with(plane + "\n    array: {count: [1000000, 1000000, 1000000]}"),
                    "scene.yaml"),
        survey_case("copies over the scene's limit in all", survey_with(""),
                    "parts:\n  - " + plane + "\n    array: {count: [1000, 1000, 1]}\n  - " + plane +
                        "\n    array: {count: [1000, 1, 1]}\n",
                    "scene.yaml"),
        // Finding 8: a 100 MiB value, and devices or oversized files given as text files.
        {"100 MiB value",
         [](const fs::path& dir, const fs::path& out) {
             test::write_file(dir / "scene.yaml", kFloor);
             test::write_file(dir / "survey.yaml",
                              survey_with("output: {point_format: " +
                                          std::string(std::size_t{100} << 20, 'v') + "}\n"));
             return survey_args(dir / "survey.yaml", out);
         },
         [](const fs::path& dir) {
             return (dir / "survey.yaml").string() +
                    ": the survey file is larger than the limit of 64 MiB";
         }},
        {"a million waypoints",
         [](const fs::path& dir, const fs::path& out) {
             std::string survey =
                 "scene: demo\nscanner: {type: line, duration_s: 0.1}\n"
                 "platform: {type: legs, waypoints_m: [";
             for (int i = 0; i < 1000000; ++i) {
                 survey += "[0,0,0],";
             }
             survey += "]}\n";
             test::write_file(dir / "survey.yaml", survey);
             return survey_args(dir / "survey.yaml", out);
         },
         [](const fs::path& dir) {
             return (dir / "survey.yaml").string() + ": more than 200000 YAML nodes";
         }},
        {"/dev/zero as the survey file",
         [](const fs::path&, const fs::path& out) { return survey_args("/dev/zero", out); },
         [](const fs::path&) { return std::string("/dev/zero: "); }},
        dev_zero_case("/dev/zero as the scene file", "scene: /dev/zero\n" + std::string(kScanner),
                      "scene"),
        dev_zero_case("/dev/zero as the trajectory file",
                      "scene: scene.yaml\nscanner: {type: line, duration_s: 0.1}\n"
                      "platform: {type: trajectory, file: /dev/zero}\n",
                      "trajectory"),
        {"/dev/zero as the rays file",
         [](const fs::path&, const fs::path& out) {
             return std::vector<std::string>{"scan",    "--demo",   "--pattern",
                                             "rays",    "--rays",   "/dev/zero",
                                             "--quiet", "--output", out.string()};
         },
         [](const fs::path&) { return std::string("/dev/zero:"); }},
        {"a rays file of one endless line",
         [](const fs::path& dir, const fs::path& out) {
             test::write_file(dir / "rays.csv", std::string(std::size_t{17} << 20, '1'));
             return std::vector<std::string>{"scan",    "--demo",   "--pattern",
                                             "rays",    "--rays",   (dir / "rays.csv").string(),
                                             "--quiet", "--output", out.string()};
         },
         [](const fs::path& dir) { return (dir / "rays.csv").string() + ":1: line longer"; }},
        {"a rays file of 8 million empty lines",
         [](const fs::path& dir, const fs::path& out) {
             test::write_file(dir / "rays.csv", std::string(std::size_t{8} << 20, '\n'));
             return std::vector<std::string>{"scan",    "--demo",   "--pattern",
                                             "rays",    "--rays",   (dir / "rays.csv").string(),
                                             "--quiet", "--output", out.string()};
         },
         [](const fs::path& dir) { return (dir / "rays.csv").string() + ": no rays found"; }},
        {"a scan image of 40000 x 40000 rays",
         [](const fs::path&, const fs::path& out) {
             return std::vector<std::string>{"scan",    "--demo",   "--width",
                                             "40000",   "--height", "40000",
                                             "--quiet", "--output", out.string()};
         },
         [](const fs::path&) {
             return std::string("width x height (40000 x 40000) must be at most 67108864 rays");
         }},
        {"a folder as the scene file",
         [](const fs::path& dir, const fs::path& out) {
             fs::create_directory(dir / "folder.yaml");
             test::write_file(dir / "survey.yaml", "scene: folder.yaml\n" + std::string(kScanner));
             return survey_args(dir / "survey.yaml", out);
         },
         [](const fs::path& dir) { return (dir / "folder.yaml").string() + ": "; }},
    };
    // The scene file: a sparse 65 MiB file, over the limit for scene files.
    cases.push_back({"a scene file over 64 MiB",
                     [](const fs::path& dir, const fs::path& out) {
                         test::write_file(dir / "scene.yaml", kFloor);
                         fs::resize_file(dir / "scene.yaml", std::size_t{65} << 20);
                         test::write_file(dir / "survey.yaml",
                                          "scene: scene.yaml\n" + std::string(kScanner));
                         return survey_args(dir / "survey.yaml", out);
                     },
                     [](const fs::path& dir) {
                         return (dir / "scene.yaml").string() +
                                ": the scene file is larger than the limit of 64 MiB";
                     }});
    return cases;
}

TEST(HostileInput, EveryReproducerExitsTwoWithOneLineNamingTheFile) {
    for (const Hostile& h : hostile_inputs()) {
        SCOPED_TRACE(h.name);
        test::TempDir dir;
        const fs::path out = dir / "out";
        std::vector<std::string> argv{BEAMTRACE_CLI_PATH};
        const std::vector<std::string> args = h.setup(dir.path(), out);
        argv.insert(argv.end(), args.begin(), args.end());
        const test::ChildPeak run = test::run_measuring_peak_rss(argv, dir / "cli.log");
        const std::string log = test::read_file(dir / "cli.log");
        EXPECT_EQ(run.exit_code, 2) << log;
        EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log.substr(0, 2000);
        EXPECT_EQ(log.rfind("beamtrace: error: ", 0), 0u) << log.substr(0, 2000);
        EXPECT_EQ(log.find("internal error"), std::string::npos) << log.substr(0, 2000);
        const std::string fragment = h.fragment(dir.path());
        EXPECT_NE(log.find(fragment), std::string::npos) << "expected '" << fragment << "' in\n"
                                                         << log.substr(0, 2000);
        EXPECT_LT(log.size(), 1000u) << "the message quotes too much";
        EXPECT_FALSE(fs::exists(out) && !fs::is_empty(out)) << "output written to " << out;
#ifndef BEAMTRACE_SANITIZED  // AddressSanitizer's shadow memory swamps the RSS
        EXPECT_TRUE(run.error.empty()) << run.error;
        EXPECT_LT(run.peak_rss_bytes, kPeakLimitBytes) << "peak RSS " << run.peak_rss_bytes;
#endif
    }
}

#ifndef BEAMTRACE_SANITIZED  // the sanitizers reserve terabytes of address space
/// Memory reserved but never touched does not show in the peak RSS: under a 1 GB address-space
/// limit, a rays file of empty lines must not reserve room for a ray per line (it used to
/// reserve 3 GB here).
TEST(HostileInput, RaysFileOfEmptyLinesReservesNothing) {
    test::TempDir dir;
    test::write_file(dir / "rays.csv", std::string(std::size_t{60} << 20, '\n'));
    const test::RunResult r =
        test::run_command("ulimit -v 1000000; '" + std::string(BEAMTRACE_CLI_PATH) +
                          "' scan --demo --pattern rays --rays '" + (dir / "rays.csv").string() +
                          "' --quiet --output '" + (dir / "out").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_EQ(r.out, "beamtrace: error: " + (dir / "rays.csv").string() +
                         ": no rays found (expected lines ox,oy,oz,dx,dy,dz)\n");
}
#endif

/// Values far longer than a message should quote (1 MiB each), in every kind of place that
/// echoes a value: each is quoted clipped to 80 characters and "...".
TEST(HostileInput, LongValuesAreQuotedClipped) {
    const std::string big(std::size_t{1} << 20, 'q');
    const std::string clipped = std::string(80, 'q') + "...";
    const std::string plane = "plane: {point_m: [0, 0, -2], normal: [0, 0, 1], size_m: 40}";
    const std::vector<Hostile> cases = {
        survey_case("unknown key", survey_with("? " + big + "\n: 1\n"), kFloor, "survey.yaml"),
        survey_case("not a number", survey_with("output:\n  trajectory_rate_hz: " + big + "\n"),
                    kFloor, "survey.yaml"),
        survey_case("scan waveform",
                    "scene: scene.yaml\nscanner:\n  type: line\n  waveform: " + big +
                        "\nplatform: {type: static}\n",
                    kFloor, "survey.yaml"),
        survey_case("return mode", survey_with("physics:\n  returns:\n    mode: " + big + "\n"),
                    kFloor, "survey.yaml"),
        survey_case("scene file name", "scene: " + big + "\n" + std::string(kScanner), kFloor,
                    "survey.yaml"),
        survey_case("material name", survey_with(""), scene_with(plane + "\n    material: " + big),
                    "scene.yaml"),
        survey_case("unknown key of a part", survey_with(""),
                    scene_with(plane + "\n    ? " + big + "\n    : 1"), "scene.yaml"),
        survey_case("mesh file name", survey_with(""), scene_with("mesh: " + big), "scene.yaml"),
    };
    for (const Hostile& h : cases) {
        SCOPED_TRACE(h.name);
        test::TempDir dir;
        const std::vector<std::string> args = h.setup(dir.path(), dir / "out");
        std::string cmd = "'" + std::string(BEAMTRACE_CLI_PATH) + "'";
        for (const auto& a : args) {
            cmd += " '" + a + "'";
        }
        const test::RunResult r = test::run_command(cmd);
        EXPECT_EQ(r.exit_code, 2) << r.out.substr(0, 2000);
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out.substr(0, 2000);
        EXPECT_NE(r.out.find(h.fragment(dir.path())), std::string::npos) << r.out.substr(0, 2000);
        EXPECT_NE(r.out.find(clipped), std::string::npos) << r.out.substr(0, 2000);
        EXPECT_LT(r.out.size(), 600u + dir.path().string().size()) << r.out.substr(0, 2000);
    }
}

}  // namespace
}  // namespace beamtrace
