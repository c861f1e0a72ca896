// What run_survey and iter_survey share: the packed point records of their structured arrays
// (the columns of docs/python.md, "Surveys") and the run settings they take from Python.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/io/point_sink.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "bindings.hpp"

namespace beamtrace::python {

/// Bytes of one packed point record (the dtype's itemsize) without the weather column.
inline constexpr std::size_t kRecordBytes = 3 * 8 + 2 + 3 + 2 + 8 + 4 + 1 + 2 + 4 + 4 + 8 + 4 * 2;

/// The records' columns: the common ones, and `weather` (u1, last) when the survey has weather.
struct RecordLayout {
    bool weather = false;
    [[nodiscard]] std::size_t bytes() const { return kRecordBytes + (weather ? 1 : 0); }
};

/// The layout of `spec`'s points: with `weather` when its physics has a `weather:` block.
[[nodiscard]] RecordLayout record_layout(const SurveySpec& spec);

/// Appends the packed records of `points` to `out`.
void append_records(std::span<const BlockPoint> points, RecordLayout layout,
                    std::vector<std::uint8_t>& out);

/// `records` (whole records) as a structured array that owns them: no copy.
[[nodiscard]] py::array records_array(std::vector<std::uint8_t>&& records, RecordLayout layout);

/// What a survey call asks of the run, besides the survey.
struct RunOptions {
    std::uint64_t seed = 1;
    unsigned threads = 0;
    std::optional<std::string> backend;
    std::uint64_t max_pulses = 0;
    std::optional<std::filesystem::path> output_dir;
};

/// The library's run settings for `o` (no extra sinks, no cancel token yet). Throws ConfigError
/// for an unknown backend.
[[nodiscard]] SurveyRunConfig run_config(const RunOptions& o);

}  // namespace beamtrace::python
