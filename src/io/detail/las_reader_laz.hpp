// The LAZ state of a LasReader (private to src/io): the LASzip VLR, the chunk table, where the
// reader stands in it, and the buffers and threads that decode a batch of chunks.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "laz/chunk_table.hpp"
#include "laz/laz_vlr.hpp"
#include "laz/pointwise_chunk.hpp"

namespace beamtrace {

struct LasReader::Laz {
    laz::LazVlr vlr;
    std::vector<laz::Chunk> chunks;
    std::size_t next_chunk = 0;  ///< the next chunk to decode
    std::uint64_t skip = 0;      ///< records of that chunk to skip (after a seek)
    std::vector<std::vector<std::uint8_t>> compressed;  ///< one buffer per chunk of a batch
    std::vector<std::string> errors;                    ///< per chunk of a batch, "" when fine
    std::unique_ptr<ThreadPool> pool;
    /// Compressor 1 (one point-wise stream of every point): decoded a batch at a time.
    std::unique_ptr<laz::PointwiseChunkDecoder> stream;
};

}  // namespace beamtrace
