// The settings of a survey's points.las (formats 6-8, no wave packets): millimetre coordinates
// around the scene, the scene's CRS in an OGC WKT VLR, the provenance VLR. Shared by the LAS sink
// and by surveys whose ranks place the records themselves (run_survey_distributed).
#pragma once

#include <span>

#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/point_sink.hpp"

namespace beamtrace {

[[nodiscard]] LasWriterConfig survey_las_config(const SinkFacts& facts);

/// Fills the extra bytes (`attributes`, SinkFacts::extra_bytes) of the last points.size()
/// records of `records`, which `writer` encoded from `points`, in order. Nothing without
/// attributes.
void encode_las_extra_bytes(std::span<const PointAttribute> attributes,
                            std::span<const BlockPoint> points, const LasWriter& writer,
                            LasRecordBlock& records);

}  // namespace beamtrace
