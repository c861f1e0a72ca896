// LAS <-> LAZ: a file's point records, VLRs and EVLRs carried over unchanged, only the storage of
// the records changing (beamtrace convert, docs/convert.md).
#pragma once

#include <cstdint>
#include <filesystem>

#include "beamtrace/core/progress.hpp"
#include "beamtrace/io/las_writer.hpp"

namespace beamtrace {

struct LasConvertConfig {
    /// How the output stores the records: none (LAS) or laz (LASzip-compressed).
    LasCompression compression = LasCompression::none;
    std::uint32_t laz_chunk_size = 50000;  ///< laz: points per chunk
    unsigned threads = 0;                  ///< LAZ chunks decoded / encoded at once (0: all cores)
};

struct LasConvertResult {
    std::uint64_t points = 0;
    bool input_compressed = false;
    std::uint64_t input_bytes = 0, output_bytes = 0;
};

/// Streams `in` (any LAS 1.0-1.4 file, formats 0-10, plain or LAZ) into `out` through
/// AtomicFile: the header, every VLR and EVLR and every point record byte for byte, except the
/// LASzip VLR (dropped; for laz a new one is appended after the other VLRs), the point format's
/// LAZ bit and the offsets and VLR count that follow from these. Memory stays bounded by a batch
/// of chunks. LAS -> LAZ -> LAS gives back the original bytes. Throws InputError naming `in`
/// for a bad input, OutputError naming `out`; `progress(done, total)` counts points.
LasConvertResult convert_las(const std::filesystem::path& in, const std::filesystem::path& out,
                             const LasConvertConfig& config, const ProgressFn& progress = {});

}  // namespace beamtrace
