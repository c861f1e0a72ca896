// Moving parts' cost (issue 20, item 4): a VLP-16 in a car park of 100 cars (10 x 10, 8 m apart)
// for 1 s, once with the cars frozen and once with all of them driving at 10 m/s, in one run:
// each iteration times both, alternating, and `moving/frozen` is the ratio of their survey pulses
// per second (target >= 0.8). `moving/frozen_cpu` is the same ratio of the process's CPU time
// over the two runs (all threads, the writer's too): on a machine shared with other work it
// follows what an idle machine's wall clock would show more closely than the wall clock does.
// Arguments: threads, and the backend (0: embree, 1: bvh). Checked before timing: the moving
// survey's points read back, and its cars' points carry their velocity.
//   build/bench/beamtrace_bench --benchmark_filter=BM_MovingInstances
#include <benchmark/benchmark.h>

#include <ctime>

#include <filesystem>
#include <fstream>
#include <string>

#include "beamtrace/io/las_extra_bytes.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/pipeline/survey.hpp"

namespace bt = beamtrace;
namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& path, const std::string& text) {
    std::ofstream(path) << text;
}

/// The car park (cars moving or not) and the survey, in `dir`; returns the survey file.
fs::path write_car_park(const fs::path& dir, bool moving) {
    fs::create_directories(dir);
    const fs::path car = fs::path(BEAMTRACE_EXAMPLES_DIR) / "scenes" / "car_boxes.obj";
    write_text(dir / "scene.yaml",
               "parts:\n"
               "  - {plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 300}, label: 2}\n"
               "  - mesh: " +
                   car.string() +
                   "\n    transform: {translate_m: [-36, -36, 0]}\n"
                   "    array: {count: [10, 10, 1], step_m: [8, 8, 0]}\n" +
                   (moving ? "    motion: {velocity_mps: [10, 0, 0]}\n" : ""));
    write_text(dir / "survey.yaml",
               "scene: scene.yaml\n"
               "scanner: {type: rotating, preset: velodyne_vlp16, duration_s: 1.0}\n"
               "platform: {type: static, position_m: [0, 4, 2.5]}\n"
               "output: {point_format: 6, trajectory_rate_hz: 0, preview: false,\n"
               "         extra_bytes: [instance_id, velocity_x]}\n");
    return dir / "survey.yaml";
}

/// The moving survey's points are all read back, and some carry a car's 10 m/s.
bool check(const bt::SurveyResult& r, const fs::path& las) {
    bt::LasReader reader(las);
    const auto fields = bt::las_extra_bytes_descriptors(reader.vlrs());
    const auto points = bt::read_las_points(las);
    std::size_t on_cars = 0;
    for (const auto& p : points) {
        on_cars += bt::las_extra_bytes_value(fields, 1, p.extra_bytes) == 10.0 ? 1 : 0;
    }
    return points.size() == r.points && r.points > 0 && on_cars > 1000;
}

/// The process's CPU time (all threads), in seconds.
double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void BM_MovingInstances(benchmark::State& state) {
    const fs::path root = fs::temp_directory_path() / "beamtrace-bench-motion";
    const bt::SurveySpec frozen = bt::load_survey_spec(write_car_park(root / "frozen", false));
    const bt::SurveySpec moving = bt::load_survey_spec(write_car_park(root / "moving", true));
    bt::SurveyRunConfig run;
    run.threads = static_cast<unsigned>(state.range(0));
    run.backend = state.range(1) == 0 ? bt::BackendKind::embree : bt::BackendKind::bvh;
    run.output_dir = root / "out";
    if (!check(bt::run_survey(moving, run), run.output_dir / "points.las")) {
        state.SkipWithError("moving survey check failed");
        return;
    }
    double frozen_s = 0, moving_s = 0, frozen_cpu_s = 0, moving_cpu_s = 0;
    std::uint64_t pulses = 0;
    for (auto _ : state) {
        const double cpu0 = cpu_seconds();
        frozen_s += bt::run_survey(frozen, run).survey_s;
        const double cpu1 = cpu_seconds();
        const bt::SurveyResult r = bt::run_survey(moving, run);
        moving_cpu_s += cpu_seconds() - cpu1;
        frozen_cpu_s += cpu1 - cpu0;
        moving_s += r.survey_s;
        pulses += r.pulses;
    }
    state.counters["frozen_pulses/s"] = static_cast<double>(pulses) / frozen_s;
    state.counters["moving_pulses/s"] = static_cast<double>(pulses) / moving_s;
    state.counters["moving/frozen"] = frozen_s / moving_s;
    state.counters["moving/frozen_cpu"] = frozen_cpu_s / moving_cpu_s;
    fs::remove_all(root);
}

BENCHMARK(BM_MovingInstances)
    ->ArgNames({"threads", "bvh"})
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({1, 1})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

}  // namespace
