#include "survey_points.hpp"

#include <array>
#include <memory>
#include <stdexcept>
#include <utility>

#include "numpy_arrays.hpp"

namespace beamtrace::python {
namespace {

/// The columns of the survey arrays, packed in this order (write_point follows it).
constexpr std::array<Field, 20> kFields{{{"x", "f8"},
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
                                         {"nir", "u2"},
                                         {"weather", "u1"}}};

void write_point(const BlockPoint& p, RecordLayout layout, std::uint8_t* record) {
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
    if (layout.weather) {
        put(p.weather);  // WeatherEffect: 0 the scene, 1 fog, 2 rain, 3 snow
    }
}

}  // namespace

RecordLayout record_layout(const SurveySpec& spec) {
    return {spec.physics.has_value() && spec.physics->weather.has_value()};
}

void append_records(std::span<const BlockPoint> points, RecordLayout layout,
                    std::vector<std::uint8_t>& out) {
    const std::size_t at = out.size();
    const std::size_t bytes = layout.bytes();
    out.resize(at + points.size() * bytes);
    for (std::size_t i = 0; i < points.size(); ++i) {
        write_point(points[i], layout, out.data() + at + i * bytes);
    }
}

py::array records_array(std::vector<std::uint8_t>&& records, RecordLayout layout) {
    const std::span<const Field> fields(kFields.data(), kFields.size() - (layout.weather ? 0 : 1));
    const py::dtype dtype = structured_dtype(fields);
    const std::size_t record_bytes = layout.bytes();
    if (static_cast<std::size_t>(dtype.itemsize()) != record_bytes) {
        throw std::logic_error("survey points: dtype is not packed");
    }
    using Records = std::vector<std::uint8_t>;
    auto owned = std::make_unique<Records>(std::move(records));
    const auto count = static_cast<py::ssize_t>(owned->size() / record_bytes);
    std::uint8_t* data = owned->data();
    py::capsule base(owned.get(), [](void* p) { delete static_cast<Records*>(p); });
    (void)owned.release();
    return py::array(dtype, {count}, {static_cast<py::ssize_t>(record_bytes)}, data, base);
}

SurveyRunConfig run_config(const RunOptions& o) {
    SurveyRunConfig run;
    run.seed = o.seed;
    run.threads = o.threads;
    if (o.backend) {
        run.backend = parse_backend_kind(*o.backend);
    }
    run.max_pulses = o.max_pulses;
    run.write_files = o.output_dir.has_value();
    run.output_dir = o.output_dir.value_or(std::filesystem::path());
    return run;
}

}  // namespace beamtrace::python
