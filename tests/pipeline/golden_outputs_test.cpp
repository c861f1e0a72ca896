// Golden digests of every output of every example survey, the demo scan and the beach-ball
// render, at 1 and 2 threads, so that a redesign of the pipeline (issue 14) can show that it
// changed no byte. The digests are in tests/data/golden_outputs.txt; after a deliberate change
// of an output, regenerate them with BEAMTRACE_UPDATE_GOLDEN=1 and say why in the commit.
// The runs use our `bvh` backend: Embree picks its kernels by CPU, so its float results may
// differ between machines, while our code is built for baseline x86-64 and gives the same bytes
// on every CPU that glibc's libm serves with the same (FMA) variants: all of CI's machines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// FNV-1a, 64 bits: enough to tell a changed byte, not a cryptographic hash.
std::uint64_t fnv1a(const std::string& bytes) {
    std::uint64_t h = 14695981039346656037ull;
    for (const char c : bytes) {
        h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    }
    return h;
}

/// The digest of an output file; a LAS file's creation day and year (header bytes 90-93) are
/// zeroed first, as they change with the date.
std::string digest(const fs::path& path) {
    std::string bytes = test::read_file(path);
    if (path.extension() == ".las" && bytes.size() >= 94) {
        std::fill(bytes.begin() + 90, bytes.begin() + 94, '\0');
    }
    char out[64];
    std::snprintf(out, sizeof out, "%016llx %zu", static_cast<unsigned long long>(fnv1a(bytes)),
                  bytes.size());
    return out;
}

struct Job {
    std::string name;
    std::string args;  ///< CLI arguments; OUT stands for the output folder, DIR for its parent
    std::string yaml;  ///< when set, written as DIR/survey.yaml first
    /// When set, copied to DIR/scene.yaml first (the survey names it by a relative path, as the
    /// LAS file records the scene's path and the digests must not depend on the checkout's).
    std::string scene_copy;
};

/// The outputs no example writes: PLY, format 8, waveforms.bin (a short physics line survey of
/// the demo scene with every output on).
constexpr const char* kAllOutputs = R"(scene: demo
scanner: {type: line, pulse_rate_hz: 20000, scan_rate_hz: 20, scan_angle_max_deg: 25,
          waveform: triangle, duration_s: 0.2}
platform: {type: legs, speed_mps: 50, waypoints_m: [[-30, 0, 150], [30, 0, 150]]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 2, rings: 1}
  noise: {range_sigma_m: 0.02}
  returns: {mode: all, max: 5}
  waveform: {pulse_fwhm_ns: 2, bin_ns: 0.5, keep: true}
output: {point_format: 8, ply: true, csv: true, trajectory_rate_hz: 10}
)";

/// A panorama of coarse steps with a wide 19-sub-ray beam, so that some pulses meet the
/// sphere targets with part of their sub-rays (the scene line is added before it).
constexpr const char* kDivergentPanorama =
    R"(scanner: {type: scan, width: 720, height: 120, hfov_deg: 360, vfov_deg: 60,
          pulse_rate_hz: 1000000, range_max_m: 60}
platform: {type: static, position_m: [0, 0, 1.5]}
physics:
  beam: {divergence_mrad: 12, rings: 2}
  returns: {mode: all, max: 5}
output: {csv: true, trajectory_rate_hz: 0}
)";

/// The beach ball seen from 6 m with a 19-sub-ray beam: each sub-ray reads the stripe or the
/// sand's checker at its own hit point.
constexpr const char* kDivergentBallView =
    R"(scanner: {type: scan, width: 160, height: 120, hfov_deg: 40, vfov_deg: 30}
platform: {type: static, position_m: [-6, 0, 1.2]}
physics:
  beam: {divergence_mrad: 20, rings: 2}
  returns: {mode: all, max: 5}
output: {csv: true, trajectory_rate_hz: 0}
)";

std::vector<Job> jobs() {
    const std::string ex = BEAMTRACE_EXAMPLES_DIR;
    std::vector<Job> all;
    std::vector<std::string> surveys;
    for (const auto& e : fs::directory_iterator(fs::path(ex) / "surveys")) {
        const std::string name = e.path().filename().string();
        // airborne_srtm_1e8.yaml writes 3 GB; under the sanitizers, the SRTM surveys take
        // minutes and run the same code as the others.
        bool skip = name == "airborne_srtm_1e8.yaml";
#ifdef BEAMTRACE_SANITIZED
        skip = skip || name.rfind("airborne_srtm", 0) == 0;
#endif
        if (e.path().extension() == ".yaml" && !skip) {
            surveys.push_back(name);
        }
    }
    std::sort(surveys.begin(), surveys.end());
    for (const auto& s : surveys) {
        all.push_back({"survey/" + s, "survey " + ex + "/surveys/" + s + " --output OUT", "", ""});
    }
    all.push_back({"survey/all_outputs", "survey DIR/survey.yaml --output OUT", kAllOutputs, ""});
    // Divergent beams over exact spheres (a normal per sub-ray hit point) and over a patterned
    // albedo (a reflectance per sub-ray hit point): the sub-rays' per-face shortcuts must not
    // share what differs between the sub-rays of one face.
    all.push_back({"survey/divergent_spheres", "survey DIR/survey.yaml --output OUT",
                   std::string("scene: scene.yaml\n") + kDivergentPanorama,
                   ex + "/scenes/sphere_targets.yaml"});
    all.push_back({"survey/divergent_ball", "survey DIR/survey.yaml --output OUT",
                   std::string("scene: scene.yaml\n") + kDivergentBallView,
                   ex + "/scenes/beach_ball.yaml"});
    all.push_back({"scan/demo", "scan --demo --outputs ply,npy,png,csv --output OUT", "", ""});
    all.push_back({"render/beach_ball",
                   "render " + ex +
                       "/scenes/beach_ball.yaml --camera -6,-4,3,0,0,40 --look-at "
                       "0,0,0.8 --light dir:-60,45,0.9 --ambient 0.15 --size 320x240 "
                       "--gamma 2.2 --output OUT/beach_ball.png",
                   "", ""});
    return all;
}

/// Runs a job and returns "job/file digest size" for every file it wrote, sorted.
std::vector<std::string> run_job(const Job& job, unsigned threads, const fs::path& out) {
    fs::create_directories(out);
    std::string args = job.args;
    for (const auto& [key, value] :
         {std::pair<std::string, std::string>{"OUT", out.string()},
          std::pair<std::string, std::string>{"DIR", out.parent_path().string()}}) {
        for (auto at = args.find(key); at != std::string::npos; at = args.find(key, at)) {
            args.replace(at, key.size(), value);
        }
    }
    if (!job.yaml.empty()) {
        test::write_file(out.parent_path() / "survey.yaml", job.yaml);
    }
    if (!job.scene_copy.empty()) {
        fs::copy_file(job.scene_copy, out.parent_path() / "scene.yaml",
                      fs::copy_options::overwrite_existing);
    }
    const auto r = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " " + args +
                                     " --backend bvh --quiet --threads " + std::to_string(threads));
    EXPECT_EQ(r.exit_code, 0) << job.name << ":\n" << r.out;
    std::vector<std::string> lines;
    for (const auto& e : fs::directory_iterator(out)) {
        lines.push_back(job.name + "/" + e.path().filename().string() + " " + digest(e.path()));
    }
    std::sort(lines.begin(), lines.end());
    return lines;
}

fs::path golden_file() {
    return fs::path(BEAMTRACE_TEST_DATA_DIR) / "golden_outputs.txt";
}

/// job/file -> "digest size" from the golden file.
std::map<std::string, std::string> read_golden() {
    std::map<std::string, std::string> golden;
    std::istringstream in(test::read_file(golden_file()));
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') {
            continue;
        }
        const auto space = line.find(' ');
        golden[line.substr(0, space)] = line.substr(space + 1);
    }
    return golden;
}

TEST(GoldenOutputs, EveryExampleOutputIsByteIdenticalToItsDigestAtOneAndTwoThreads) {
    const char* update = std::getenv("BEAMTRACE_UPDATE_GOLDEN");
    const bool updating = update != nullptr && std::string(update) == "1";
    const auto golden = updating ? std::map<std::string, std::string>{} : read_golden();
    std::string regenerated =
        "# Digests of example outputs (tests/pipeline/golden_outputs_test.cpp): job/file "
        "fnv1a64 bytes\n";
    std::size_t checked = 0;
    for (const Job& job : jobs()) {
        test::TempDir dir;
        const auto one = run_job(job, 1, dir / "t1");
        const auto two = run_job(job, 2, dir / "t2");
        EXPECT_EQ(one, two) << job.name << ": outputs differ between 1 and 2 threads";
        for (const auto& line : one) {
            regenerated += line + "\n";
            const auto space = line.find(' ');
            const std::string key = line.substr(0, space);
            if (updating) {
                continue;
            }
            const auto it = golden.find(key);
            if (it == golden.end()) {
                ADD_FAILURE() << key << " has no golden digest (BEAMTRACE_UPDATE_GOLDEN=1)";
                continue;
            }
            EXPECT_EQ(line.substr(space + 1), it->second) << key << " changed";
            ++checked;
        }
    }
    if (updating) {
        test::write_file(golden_file(), regenerated);
        std::printf("  wrote %s\n", golden_file().string().c_str());
        return;
    }
#ifndef BEAMTRACE_SANITIZED
    EXPECT_EQ(checked, golden.size()) << "the golden file lists outputs no job wrote";
#endif
    EXPECT_GT(checked, 20u);
}

}  // namespace
}  // namespace beamtrace
