// A point sink that writes no file: it hands each block's points to a callback, in block order,
// with the coordinates and scan angles that points.las decodes to. The in-memory output of a
// survey (SurveyRunConfig::extra_sinks; the Python module's run_survey), equal to the LAS file
// point for point.
#pragma once

#include <functional>
#include <memory>
#include <span>

#include "beamtrace/io/point_sink.hpp"

namespace beamtrace {

/// Receives one block's points, on the writer thread, blocks in order; the span is valid until
/// it returns. An exception it throws aborts the run.
using PointBlockFn = std::function<void(std::span<const BlockPoint>)>;

/// A sink calling `fn` with every block's points. x, y, z and scan_angle_deg are those of
/// points.las as a reader decodes them: quantised with the LAS sink's scale and offset
/// (las_config_for_extent(facts.lo_m, facts.hi_m, 0.001)) and to 0.006 degree steps; the other
/// fields are the pipeline's. commit() returns no file. A coordinate that points.las could not
/// store throws OutputError, as the LAS sink does.
[[nodiscard]] std::unique_ptr<PointSink> make_callback_sink(const SinkFacts& facts,
                                                            PointBlockFn fn);

}  // namespace beamtrace
