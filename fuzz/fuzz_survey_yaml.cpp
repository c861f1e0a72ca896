// libFuzzer target: survey files (parse_survey_spec on the input as YAML text), then the scan
// pattern and trajectory they describe. The survey's folder holds an empty scene.yaml and a
// trajectory.csv, so that seeds naming them pass the existence checks and reach the rest.
#include <cstddef>
#include <cstdint>

#include "beamtrace/pipeline/survey.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool files_made = [] {
        const std::uint8_t header[] =
            "time_s,x,y,z,roll,pitch,yaw\n0,0,0,100,0,0,0\n1,10,0,100,0,0,0\n";
        (void)beamtrace::fuzz::write_input(header, sizeof header - 1, "trajectory.csv");
        (void)beamtrace::fuzz::write_input(header, 0, "scene.yaml");
        return true;
    }();
    (void)files_made;
    const auto text = beamtrace::fuzz::as_text(data, size);
    const auto source = beamtrace::fuzz::scratch_dir() / "survey.yaml";
    return beamtrace::fuzz::run_guarded([&] {
        const beamtrace::SurveySpec spec = beamtrace::parse_survey_spec(text, source);
        (void)spec.make_pattern();
        (void)spec.make_trajectory();
    });
}
