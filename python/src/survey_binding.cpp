// beamtrace.run_survey (docs/python.md): a survey from a file or from survey text (a dict as
// JSON, made by the package's __init__.py) run in memory through the library's callback sink,
// into a NumPy structured array in the order of the CLI's points.las.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/io/callback_sink.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "bindings.hpp"
#include "survey_points.hpp"
#include "watched_run.hpp"

namespace beamtrace::python {
namespace {

py::array run(const SurveySpec& spec, const RunOptions& o, const py::object& progress) {
    SurveyRunConfig run = run_config(o);
    auto records = std::make_unique<std::vector<std::uint8_t>>();
    const RecordLayout layout = record_layout(spec);
    run.extra_sinks.emplace_back([out = records.get(), layout](const SinkFacts& facts) {
        return make_callback_sink(facts, [out, layout](std::span<const BlockPoint> points) {
            append_records(points, layout, *out);
        });
    });
    run_watched(
        [&](const CancelToken& cancel, const ProgressFn& report) {
            run.cancel = &cancel;
            (void)run_survey(spec, run, report);
        },
        progress);
    return records_array(std::move(*records), layout);
}

void add_run_survey(py::module_& m, const char* name, SurveySpec (*load)(const std::string&),
                    const char* doc) {
    m.def(
        name,
        [load](const std::string& survey, std::uint64_t seed, unsigned threads,
               std::optional<std::string> backend, std::uint64_t max_pulses,
               const py::object& progress, std::optional<std::filesystem::path> output_dir) {
            const SurveySpec spec = load(survey);
            return run(
                spec,
                RunOptions{seed, threads, std::move(backend), max_pulses, std::move(output_dir)},
                progress);
        },
        doc, py::arg("survey"), py::arg("seed") = 1, py::arg("threads") = 0u,
        py::arg("backend") = py::none(), py::arg("max_pulses") = 0,
        py::arg("progress") = py::none(), py::arg("output_dir") = py::none());
}

}  // namespace

void bind_survey(py::module_& m) {
    add_run_survey(
        m, "_run_survey_file", [](const std::string& path) { return load_survey_spec(path); },
        "run_survey on a survey file (see beamtrace.run_survey)");
    // A dict's paths resolve against the current directory: a source with no folder.
    add_run_survey(
        m, "_run_survey_text",
        [](const std::string& text) { return parse_survey_spec(text, "<dict>"); },
        "run_survey on survey text, YAML or JSON (see beamtrace.run_survey)");
    bind_survey_blocks(m);
}

}  // namespace beamtrace::python
