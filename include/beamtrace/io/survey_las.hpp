// The settings of a survey's points.las (formats 6-8, no wave packets): millimetre coordinates
// around the scene, the scene's CRS in an OGC WKT VLR, the provenance VLR. Shared by the LAS sink
// and by surveys whose ranks place the records themselves (run_survey_distributed).
#pragma once

#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/point_sink.hpp"

namespace beamtrace {

[[nodiscard]] LasWriterConfig survey_las_config(const SinkFacts& facts);

}  // namespace beamtrace
