// Runs a survey file written into a temporary folder and reads its LAS output back.
#pragma once

#include <string>
#include <vector>

#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "test_support.hpp"

namespace beamtrace::test {

/// A closed 20 m box room (floor label 2, ceiling 3, walls 6) around the origin, as a scene file.
constexpr const char* kBoxRoom = R"(parts:
  - {plane: {point_m: [0, 0, -5], normal: [0, 0, 1], size_m: 20}, label: 2}
  - {plane: {point_m: [0, 0, 5], normal: [0, 0, -1], size_m: 20}, label: 3}
  - {plane: {point_m: [10, 0, 1.5], normal: [-1, 0, 0], size_m: 20}, label: 6}
  - {plane: {point_m: [-10, 0, 1.5], normal: [1, 0, 0], size_m: 20}, label: 6}
  - {plane: {point_m: [0, 10, 1.5], normal: [0, -1, 0], size_m: 20}, label: 6}
  - {plane: {point_m: [0, -10, 1.5], normal: [0, 1, 0], size_m: 20}, label: 6}
)";

/// Writes `yaml` as survey.yaml in `dir` and runs it into dir/out.
inline void run_survey_in(const std::string& yaml, const TempDir& dir, unsigned threads,
                          std::size_t chunk, std::uint64_t seed) {
    write_file(dir / "survey.yaml", yaml);
    const SurveySpec spec = load_survey_spec(dir / "survey.yaml");
    SurveyRunConfig run;
    run.output_dir = dir / "out";
    run.threads = threads;
    run.chunk_pulses = chunk;
    run.seed = seed;
    (void)run_survey(spec, run);
}

/// run_survey_in, then dir/out/points.las read back by our reader.
inline std::vector<LasPoint> run_and_read(const std::string& yaml, const TempDir& dir,
                                          unsigned threads = 2, std::size_t chunk = 1 << 16,
                                          std::uint64_t seed = SurveyRunConfig{}.seed) {
    run_survey_in(yaml, dir, threads, chunk, seed);
    return read_las_points(dir / "out" / "points.las");
}

}  // namespace beamtrace::test
