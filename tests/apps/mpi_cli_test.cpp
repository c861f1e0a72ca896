// `mpirun -n N beamtrace survey` (built with MPI only: BEAMTRACE_TEST_MPI): one points.las equal
// to the one-process output for 1-3 ranks and 1-2 threads per rank, with physics on; a rank that
// dies leaves no points.las and a non-zero exit; a malformed survey gives one error line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "test_support.hpp"

#ifdef BEAMTRACE_TEST_MPI

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// mpirun as root and with more ranks than cores where needed.
std::string mpirun(int ranks) {
    std::string cmd = "mpirun --oversubscribe -n " + std::to_string(ranks) + " ";
    if (::geteuid() == 0) {
        cmd += "--allow-run-as-root ";
    }
    return cmd;
}

/// Example survey `name` copied into `dir` with points.las and trajectory.csv as its only
/// outputs and, for the car, a physics block (a divergent beam, range noise).
fs::path example_copy(const std::string& name, const fs::path& dir) {
    std::string text =
        test::read_file(fs::path(BEAMTRACE_EXAMPLES_DIR) / "surveys" / (name + ".yaml"));
    if (text.find("\nphysics:") == std::string::npos) {
        text +=
            "\nphysics:\n  beam: {divergence_mrad: 3, rings: 1}\n"
            "  noise: {range_sigma_m: 0.01}\n";
    }
    // Shorter runs: 0.3 s of the car's 1.28 M pulses/s, 0.6 s of the aircraft's 100 k/s.
    for (const std::string from : {"duration_s: 1.0", "duration_s: 3.0"}) {
        if (const auto at = text.find(from); at != std::string::npos) {
            text.replace(at, from.size(),
                         from == "duration_s: 1.0" ? "duration_s: 0.3" : "duration_s: 0.6");
        }
    }
    if (const auto at = text.find("\noutput:"); at != std::string::npos) {
        text = text.substr(0, at);  // the examples end with their output block
    }
    text += "\noutput:\n  preview: false\n  trajectory_rate_hz: 10\n";
    return test::write_file(dir / (name + ".yaml"), text);
}

TEST(MpiCli, RanksAndThreadsWriteTheOneProcessFile) {
    for (const std::string name : {"car_hdl64", "airborne_line_physics"}) {
        test::TempDir dir;
        const fs::path survey = example_copy(name, dir.path());
        const auto single =
            test::run_command(std::string(BEAMTRACE_CLI_PATH) + " survey " + survey.string() +
                              " --quiet --output " + (dir / "single").string());
        ASSERT_EQ(single.exit_code, 0) << single.out;
        const std::string expected = test::read_file(dir / "single" / "points.las");
        for (const int ranks : {1, 2, 3}) {
            for (const int threads : {1, 2}) {
                SCOPED_TRACE(name + ": " + std::to_string(ranks) + " ranks x " +
                             std::to_string(threads) + " threads");
                const fs::path out = dir / (std::to_string(ranks) + "x" + std::to_string(threads));
                const auto r = test::run_command(
                    mpirun(ranks) + BEAMTRACE_CLI_PATH + " survey " + survey.string() +
                    " --quiet --threads " + std::to_string(threads) + " --output " + out.string());
                ASSERT_EQ(r.exit_code, 0) << r.out;
                EXPECT_TRUE(test::read_file(out / "points.las") == expected);
                EXPECT_EQ(test::read_file(out / "trajectory.csv"),
                          test::read_file(dir / "single" / "trajectory.csv"));
            }
        }
    }
}

TEST(MpiCli, ARankThatDiesLeavesNoOutputFile) {
    test::TempDir dir;
    const fs::path survey = example_copy("car_hdl64", dir.path());
    // Rank 1 aborts once 150 000 of the 384 k pulses are done (after the second of three
    // rounds of 2 x 64 blocks).
    const auto r = test::run_command("BEAMTRACE_TEST_MPI_ABORT=1:150000 " + mpirun(2) +
                                     BEAMTRACE_CLI_PATH + " survey " + survey.string() +
                                     " --quiet --threads 1 --output " + (dir / "out").string());
    EXPECT_NE(r.exit_code, 0) << r.out;
    EXPECT_FALSE(fs::exists(dir / "out" / "points.las")) << r.out;
}

TEST(MpiCli, AMalformedSurveyGivesOneErrorLineAndExitTwo) {
    test::TempDir dir;
    test::write_file(dir / "bad.yaml",
                     "scene: demo\nscanner: {type: rotating, preset: vlp17}\n"
                     "platform: {type: static, position_m: [0, 0, 2]}\n");
    const auto r =
        test::run_command(mpirun(3) + BEAMTRACE_CLI_PATH + " survey " +
                          (dir / "bad.yaml").string() + " --output " + (dir / "out").string());
    EXPECT_NE(r.exit_code, 0);
    std::istringstream lines(r.out);
    std::size_t ours = 0;
    for (std::string line; std::getline(lines, line);) {
        ours += line.rfind("beamtrace: error: ", 0) == 0 ? 1 : 0;
    }
    EXPECT_EQ(ours, 1u) << r.out;
    EXPECT_NE(r.out.find("scanner.preset: unknown preset"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace beamtrace

#endif  // BEAMTRACE_TEST_MPI
