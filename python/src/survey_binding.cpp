// beamtrace.run_survey (docs/python.md): a survey from a file or from survey text (a dict as
// JSON, made by the package's __init__.py) run in memory through the library's callback sink,
// into a NumPy structured array in the order of the CLI's points.las.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/io/callback_sink.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "bindings.hpp"
#include "numpy_arrays.hpp"
#include "watched_run.hpp"

namespace beamtrace::python {
namespace {

/// The columns of run_survey's array, packed in this order (write_point follows it).
constexpr std::array<Field, 19> kFields{{{"x", "f8"},
                                         {"y", "f8"},
                                         {"z", "f8"},
                                         {"intensity", "u2"},
                                         {"return_number", "u1"},
                                         {"number_of_returns", "u1"},
                                         {"classification", "u1"},
                                         {"point_source_id", "u2"},
                                         {"gps_time", "f8"},
                                         {"scan_angle", "f4"},
                                         {"user_data", "u1"},
                                         {"channel", "u2"},
                                         {"range_m", "f4"},
                                         {"face", "u4"},
                                         {"pulse", "u8"},
                                         {"red", "u2"},
                                         {"green", "u2"},
                                         {"blue", "u2"},
                                         {"nir", "u2"}}};
constexpr std::size_t kRecordBytes = 3 * 8 + 2 + 3 + 2 + 8 + 4 + 1 + 2 + 4 + 4 + 8 + 4 * 2;

py::dtype point_dtype() {
    return structured_dtype(kFields);
}

void write_point(const BlockPoint& p, std::uint8_t* record) {
    std::size_t at = 0;
    const auto put = [&](const auto value) { put_field(record, at, value); };
    put(p.x);
    put(p.y);
    put(p.z);
    put(p.intensity);
    put(p.return_number);
    put(p.number_of_returns);
    put(p.classification);
    put(p.point_source_id);
    put(p.gps_time);
    put(p.scan_angle_deg);
    put(p.user_data);
    put(p.channel);
    put(p.range_m);
    put(p.face);
    put(p.pulse);
    put(p.red);
    put(p.green);
    put(p.blue);
    put(p.nir);
}

/// What run_survey asks of the run, besides the survey.
struct RunOptions {
    std::uint64_t seed = 1;
    unsigned threads = 0;
    std::optional<std::string> backend;
    std::uint64_t max_pulses = 0;
    std::optional<std::filesystem::path> output_dir;
};

py::array run(const SurveySpec& spec, const RunOptions& o, const py::object& progress) {
    SurveyRunConfig run;
    run.seed = o.seed;
    run.threads = o.threads;
    if (o.backend) {
        run.backend = parse_backend_kind(*o.backend);
    }
    run.max_pulses = o.max_pulses;
    run.write_files = o.output_dir.has_value();
    run.output_dir = o.output_dir.value_or(std::filesystem::path());
    auto records = std::make_unique<std::vector<std::uint8_t>>();
    run.extra_sinks.emplace_back([out = records.get()](const SinkFacts& facts) {
        return make_callback_sink(facts, [out](std::span<const BlockPoint> points) {
            const std::size_t at = out->size();
            out->resize(at + points.size() * kRecordBytes);
            for (std::size_t i = 0; i < points.size(); ++i) {
                write_point(points[i], out->data() + at + i * kRecordBytes);
            }
        });
    });
    run_watched(
        [&](const CancelToken& cancel, const ProgressFn& report) {
            run.cancel = &cancel;
            (void)run_survey(spec, run, report);
        },
        progress);
    const py::dtype dtype = point_dtype();
    if (static_cast<std::size_t>(dtype.itemsize()) != kRecordBytes) {
        throw std::logic_error("run_survey: point dtype is not packed");
    }
    const auto count = static_cast<py::ssize_t>(records->size() / kRecordBytes);
    std::uint8_t* data = records->data();
    py::capsule base(records.get(),
                     [](void* p) { delete static_cast<std::vector<std::uint8_t>*>(p); });
    (void)records.release();
    return py::array(dtype, {count}, {static_cast<py::ssize_t>(kRecordBytes)}, data, base);
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
}

}  // namespace beamtrace::python
