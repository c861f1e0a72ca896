// The point data of a LAZ file as a stream of raw records in, compressed chunks out: records are
// buffered a chunk at a time, a batch of full chunks (one per thread) is encoded in parallel and
// the chunks are emitted in order, so the bytes are the same at any thread count and memory
// stays bounded by one batch. Shared by LasWriter (compression laz) and convert_las.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/las.hpp"
#include "laz/chunk_table.hpp"
#include "laz/laz_vlr.hpp"

namespace beamtrace::detail {

/// The LASzip VLR (user "laszip encoded", record 22204) for records of `point_format` with
/// `record_length` bytes, `chunk_size` points per chunk. Throws OutputError naming `path`.
[[nodiscard]] LasVlr laszip_vlr(int point_format, std::size_t record_length,
                                std::uint32_t chunk_size, const std::filesystem::path& path);

class LazChunkWriter {
  public:
    /// Writes `size` bytes at the end of the file.
    using Emit = std::function<void(const std::uint8_t* data, std::size_t size)>;

    /// `first_chunk_offset`: the file offset of the first chunk's first byte (the point data
    /// start + 8, after the chunk table's offset). `threads`: chunks encoded at once (0: one per
    /// hardware thread). Errors name `path`.
    LazChunkWriter(laz::LazVlr vlr, unsigned threads, std::uint64_t first_chunk_offset, Emit emit,
                   std::filesystem::path path);
    ~LazChunkWriter();
    LazChunkWriter(const LazChunkWriter&) = delete;
    LazChunkWriter& operator=(const LazChunkWriter&) = delete;

    /// Appends `count` raw records (count * record length bytes).
    void append(const std::uint8_t* records, std::size_t count);
    /// Encodes and emits what is buffered (the last chunk may be short) and returns the chunk
    /// table, to be written at table_offset(). Nothing may be appended afterwards.
    [[nodiscard]] std::vector<std::uint8_t> finish();

    /// The file offset after the last chunk emitted: where the chunk table goes.
    [[nodiscard]] std::uint64_t table_offset() const { return offset_; }
    /// The chunks emitted so far.
    [[nodiscard]] const std::vector<laz::Chunk>& chunks() const { return chunks_; }

  private:
    void encode_buffered();

    laz::LazVlr vlr_;
    std::size_t record_length_;
    std::size_t chunk_points_;
    std::unique_ptr<ThreadPool> pool_;
    std::size_t batch_chunks_;
    std::vector<std::uint8_t> records_;               ///< a batch of chunks' raw records
    std::size_t buffered_ = 0;                        ///< records in records_
    std::vector<std::vector<std::uint8_t>> encoded_;  ///< one per chunk of a batch
    std::vector<laz::Chunk> chunks_;
    std::uint64_t offset_;
    std::uint64_t points_ = 0;  ///< points emitted
    Emit emit_;
    std::filesystem::path path_;
};

}  // namespace beamtrace::detail
