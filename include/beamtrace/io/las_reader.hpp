// Streaming reader for LAS 1.0-1.4 files, point data record formats 0-10, uncompressed or LAZ
// (LASzip-compressed: formats 0-5 point-wise, 6-10 layered; COPC files are LAZ 1.4).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include "beamtrace/io/las.hpp"

namespace beamtrace {

struct LazBatch;  // src/io/detail/las_reader_laz.hpp

/// Opens a LAS file, parses and validates the header, VLRs and EVLRs, and then streams the points
/// in chunks, so that files larger than memory can be read:
///
///     LasReader reader(path);
///     std::vector<LasPoint> chunk(LasReader::kChunkPoints);
///     while (const std::size_t n = reader.read(chunk)) { use(std::span(chunk).first(n)); }
///
/// Every problem found while opening or reading throws InputError naming the file and the part
/// of it at fault (header field, VLR number, point data): bad signature, unsupported version,
/// unknown point format, record length smaller than the format's, point data inside the header,
/// VLRs running into the point data, fewer points than the header says, EVLRs outside the file,
/// and for LAZ a bad LASzip VLR or chunk table, or a corrupt chunk (named by its number). A file
/// whose header claims 0 points is fine.
///
/// A LAZ file reads exactly like its uncompressed twin: the header's point format has the LAZ
/// bits cleared, and read() returns the same points. Its chunks are decoded a batch at a time
/// (one chunk per thread, in parallel), so memory stays bounded by a few chunks.
class LasReader {
  public:
    /// Points decoded per chunk: the reader holds kChunkPoints raw records at most.
    static constexpr std::size_t kChunkPoints = std::size_t{1} << 16;
    /// EVLR payloads larger than this (waveform data) are not loaded: their `data` stays empty.
    static constexpr std::uint64_t kMaxLoadedEvlrBytes = std::uint64_t{64} << 20;

    /// `threads`: how many LAZ chunks are decoded in parallel (0: one per hardware thread).
    explicit LasReader(std::filesystem::path path, unsigned threads = 0);
    ~LasReader();
    LasReader(const LasReader&) = delete;
    LasReader& operator=(const LasReader&) = delete;
    LasReader(LasReader&&) = delete;
    LasReader& operator=(LasReader&&) = delete;

    [[nodiscard]] const LasHeader& header() const { return header_; }
    /// The VLRs in file order, then the EVLRs (`extended` set).
    [[nodiscard]] const std::vector<LasVlr>& vlrs() const { return vlrs_; }
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }
    /// Whether the file is LAZ (its records are decoded from compressed chunks).
    [[nodiscard]] bool compressed() const { return laz_ != nullptr; }
    /// Points not yet returned by read().
    [[nodiscard]] std::uint64_t points_remaining() const { return header_.point_count - next_; }

    /// Decodes the next min(out.size(), points_remaining()) points into `out` and returns how
    /// many; 0 at the end. Reuses the points' extra_bytes storage, so reading into the same span
    /// again allocates nothing.
    std::size_t read(std::span<LasPoint> out);

    /// Copies the next min(out.size() / point_record_length, points_remaining()) raw records (as
    /// an uncompressed file holds them: a LAZ file's decoded) into `out`; returns how many. For
    /// loaders that pick fields from the records themselves.
    std::size_t read_records(std::span<std::uint8_t> out);

    /// Continues reading at point `index` (<= point count).
    void seek(std::uint64_t index);

    /// Decodes one raw point record of this file's format (point_record_length bytes).
    void decode(const std::uint8_t* record, LasPoint& out) const;

  private:
    void parse_header(std::uint64_t file_size);
    void parse_vlrs();
    void parse_evlrs(std::uint64_t file_size);
    void read_exact(void* data, std::size_t size, std::uint64_t offset, const char* what) const;
    void fill_chunk();
    [[noreturn]] void fail(const std::string& what) const;
    // The LAZ path (src/io/las_reader_laz.cpp).
    struct Laz;
    void open_laz(std::uint64_t file_size);
    void fill_laz_chunk();
    void decode_laz_batch(LazBatch& batch, std::size_t first) const;
    void start_laz_batch(std::size_t first);
    void fill_laz_stream();
    void seek_laz(std::uint64_t index);

    std::filesystem::path path_;
    int fd_ = -1;
    LasHeader header_;
    std::vector<LasVlr> vlrs_;
    std::vector<std::uint8_t> chunk_;  ///< raw records
    std::size_t chunk_points_ = 0;     ///< records in chunk_
    std::size_t chunk_next_ = 0;       ///< next record of chunk_ to decode
    std::uint64_t next_ = 0;           ///< index of the next point read() returns
    std::uint64_t file_next_ = 0;      ///< index of the next record to load from the file
    bool compressed_ = false;          ///< the point format byte has a LAZ bit
    std::size_t laszip_vlr_ = 0;       ///< 1 + index in vlrs_ of the LASzip VLR, 0: none
    unsigned threads_ = 0;
    std::unique_ptr<Laz> laz_;  ///< set for a LAZ file
};

/// All points of a LAS file (convenience for small files; use LasReader to stream).
[[nodiscard]] std::vector<LasPoint> read_las_points(const std::filesystem::path& path);

}  // namespace beamtrace
