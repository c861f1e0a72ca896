// The LAZ state of a LasReader (private to src/io): the LASzip VLR, the chunk table, where the
// reader stands in it, and the buffers and threads that decode a batch of chunks.
#pragma once

#include <future>
#include <memory>
#include <string>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "laz/chunk_table.hpp"
#include "laz/laz_vlr.hpp"
#include "laz/pointwise_chunk.hpp"

namespace beamtrace {

/// Consecutive chunks decoded together, one per pool thread at a time.
struct LazBatch {
    std::size_t first = 0;  ///< its first chunk
    std::size_t count = 0;  ///< how many chunks
    std::uint64_t points = 0;
    std::vector<std::uint8_t> records;                  ///< the decoded records
    std::vector<std::size_t> starts;                    ///< byte offset of each chunk's records
    std::vector<std::vector<std::uint8_t>> compressed;  ///< one buffer per chunk
    std::vector<std::string> errors;                    ///< per chunk, "" when fine
};

struct LasReader::Laz {
    laz::LazVlr vlr;
    std::vector<laz::Chunk> chunks;
    std::size_t next_chunk = 0;  ///< the first chunk not yet handed to the reader
    std::uint64_t skip = 0;      ///< records of that chunk to skip (after a seek)
    std::vector<std::vector<std::uint8_t>> compressed;  ///< compressor 1: the one stream
    std::unique_ptr<ThreadPool> pool;
    /// Compressor 1 (one point-wise stream of every point): decoded a batch at a time.
    std::unique_ptr<laz::PointwiseChunkDecoder> stream;
    /// Compressors 2 and 3: the batch that follows the one the reader holds is decoded while
    /// the reader's caller works on that one (`ahead` is valid once `ready` has been waited for).
    LazBatch ahead;
    std::future<void> ready;  ///< last member: destroyed (waited for) before the buffers
};

}  // namespace beamtrace
