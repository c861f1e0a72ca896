// The point data of a LAZ file as a stream of raw records in, compressed chunks out: records are
// buffered a chunk at a time; each full chunk is handed to the encoder threads while the caller
// goes on appending, and chunks are emitted in order on the caller's thread as they are done,
// so the bytes are the same at any thread count and memory stays bounded by threads + 2 chunks.
// Shared by LasWriter (compression laz) and convert_las.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

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
    /// A chunk being filled, encoded or waiting to be emitted.
    struct Slot {
        std::vector<std::uint8_t> records;
        std::size_t count = 0;  ///< records in it
        std::vector<std::uint8_t> encoded;
        bool done = false;  ///< encoded (guarded by mutex_)
        std::exception_ptr error;
    };

    void submit_filling();
    /// Emits the oldest chunk in flight, waiting for it when `wait`; false if it was not done.
    bool emit_oldest(bool wait);
    void encode(Slot& slot) const;
    void worker_loop();

    laz::LazVlr vlr_;
    std::size_t record_length_;
    std::size_t chunk_points_;
    std::vector<Slot> slots_;  ///< a ring: oldest_ .. oldest_ + in_flight_ - 1 are submitted
    std::size_t oldest_ = 0, in_flight_ = 0;
    std::vector<laz::Chunk> chunks_;
    std::uint64_t offset_;
    std::uint64_t points_ = 0;  ///< points emitted
    Emit emit_;
    std::filesystem::path path_;
    std::mutex mutex_;
    std::condition_variable work_, done_;
    std::deque<Slot*> queue_;
    bool stop_ = false;
    std::vector<std::thread> workers_;
};

}  // namespace beamtrace::detail
