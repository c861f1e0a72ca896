// Streaming writer for LAS 1.4 files with point data record formats 6-10, plain or LAZ.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/aabb.hpp"
#include "beamtrace/core/vec3.hpp"
#include "beamtrace/io/las.hpp"

namespace beamtrace {

class AtomicFile;
namespace detail {
class DirectSink;
class LazChunkWriter;
}  // namespace detail

/// The fields of a point as a simulator makes it; the record's other fields (flags, colours,
/// NIR, extra bytes) are zero. Cheaper to fill and encode than a LasPoint.
struct LasSimplePoint {
    double x = 0.0, y = 0.0, z = 0.0;  ///< scaled and offset
    double gps_time = 0.0;
    float scan_angle_deg = 0.0f;
    std::uint16_t intensity = 0;
    std::uint16_t point_source_id = 0;
    std::uint8_t return_number = 0;
    std::uint8_t number_of_returns = 0;
    std::uint8_t classification = 0;
    std::uint8_t user_data = 0;
    std::uint16_t red = 0, green = 0, blue = 0;  ///< formats 7, 8, 10
    std::uint16_t nir = 0;                       ///< formats 8, 10
    std::uint8_t scanner_channel = 0;            ///< 0-3 (the LAS 1.4 formats 6-10 all have it)
};

/// Where the wave packets of formats 9 and 10 are (global encoding bit 1 or 2).
enum class LasWaveformStorage : std::uint8_t {
    none,      ///< formats 6-8
    internal,  ///< the Waveform Data Packets EVLR of the LAS file (close_with_waveform_data)
    external,  ///< a `.wdp` file beside it, written by the caller
};

/// A point's wave packet fields (formats 9, 10; see io/las_wave_packets.hpp).
struct LasWavePacket {
    std::uint8_t descriptor_index = 0;  ///< 0: no waveform
    std::uint64_t offset = 0;           ///< from the start of the packet record's header
    std::uint32_t size = 0;             ///< bytes
    float location_ps = 0.0f;           ///< from the first sample to the point
    float dx = 0.0f, dy = 0.0f, dz = 0.0f;
};

/// How LasWriter stores the point records.
enum class LasCompression : std::uint8_t {
    none,  ///< plain LAS
    laz,   ///< LASzip-compressed (LAZ): the format byte's bit 7, the LASzip VLR, chunks
};

/// Point records encoded away from the writer (LasWriter::encode into a block, on any thread),
/// appended in order by LasWriter::write_block: the bytes plus what the header needs of them.
struct LasRecordBlock {
    std::vector<std::uint8_t> bytes;  ///< the first count records (may be longer: reused space)
    std::size_t count = 0;
    std::int32_t lo[3] = {0, 0, 0};  ///< integer bounds of the block's points (count > 0)
    std::int32_t hi[3] = {0, 0, 0};
    std::array<std::uint64_t, 15> by_return{};
    /// Empties the block (keeps its bytes allocated for reuse).
    void clear();
};

/// Adds `block`'s count, bounds and counts by return to `totals` (its bytes untouched).
void las_add_totals(LasRecordBlock& totals, const LasRecordBlock& block);

/// What LasWriter writes besides the points. Defaults give a valid LAS 1.4 / format 6 file with
/// millimetre coordinates around the origin (±2147 km); use las_config_for_extent() for data
/// elsewhere.
/// The step of the scan angle of point formats 6-10 (a signed 16-bit count of 0.006 degree).
inline constexpr double kScanAngleStepDeg = 0.006;

struct LasWriterConfig {
    /// 6 (GPS time), 7 (+ RGB), 8 (+ RGB + NIR), 9 (6 + wave packet) or 10 (8 + wave packet)
    int point_format = 6;
    /// Formats 9 and 10 need internal or external, and Wave Packet Descriptor VLRs in `vlrs`.
    LasWaveformStorage waveform_storage = LasWaveformStorage::none;
    Vec3d scale{0.001, 0.001, 0.001};
    Vec3d offset{0.0, 0.0, 0.0};
    std::string system_identifier = "beamtrace";                       ///< <= 32 characters
    std::string generating_software = "beamtrace " BEAMTRACE_VERSION;  ///< <= 32 characters
    /// Written in order: those with `extended` set as EVLRs after the points, the others as VLRs
    /// (payload < 64 KiB) before them.
    std::vector<LasVlr> vlrs;
    /// Global encoding bit 0: GPS times are adjusted standard GPS time (else GPS week seconds).
    bool gps_time_is_standard = true;
    std::uint16_t file_source_id = 0;
    /// File creation date; both 0 (the default) means today (UTC).
    std::uint16_t creation_day_of_year = 0;
    std::uint16_t creation_year = 0;
    /// Bytes appended to every record; each point's extra_bytes must have exactly this size.
    /// Describe them with an Extra Bytes VLR (LASF_Spec / 4) in `vlrs`.
    std::uint16_t extra_bytes_per_point = 0;
    /// laz: LASzip-compressed records (a .laz file, read back by LasReader and LASzip); the
    /// header's counts and bounds are those of the points, as for none.
    LasCompression compression = LasCompression::none;
    /// laz: points per chunk (the last chunk may be shorter), 1 to 4294967294.
    std::uint32_t laz_chunk_size = 50000;
    /// laz: chunks encoded at once (0: one per hardware thread), on threads of the writer's own
    /// while records keep coming; the file is the same for any value, and the writer holds at
    /// most `threads` + 2 chunks of records.
    unsigned threads = 0;

    /// Every problem with these settings (empty when they are usable).
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// A config whose offset is the rounded centre of [lo, hi] and whose scale is `resolution_m`, or
/// the next coarser 1-2-5 step where the extent would not fit in 32-bit integers at that
/// resolution. Throws ConfigError for non-finite or inverted bounds or a resolution <= 0.
[[nodiscard]] LasWriterConfig las_config_for_extent(const Vec3d& lo, const Vec3d& hi,
                                                    double resolution_m = 0.001);
[[nodiscard]] LasWriterConfig las_config_for_extent(const Aabb& box, double resolution_m = 0.001);

/// Writes a LAS 1.4 file through AtomicFile: points are streamed to disk chunk by chunk (memory
/// stays bounded), and close() writes the EVLRs, seeks back to finalize the header (bounds,
/// counts, counts by return) and renames the file into place. Until close() succeeds nothing
/// appears under `path`; a writer destroyed without close() (or after an error) leaves nothing.
///
/// Coordinates are quantized to the nearest integer step; one that does not fit in int32 with
/// the configured scale and offset throws OutputError naming the point and the value, as do
/// fields out of their range (return number > 15, scanner channel > 3, |scan angle| > 180 deg,
/// extra bytes of the wrong size). After any exception the writer accepts nothing more.
///
/// With `compression` laz the file is LAZ (LASzip): the format byte's bit 7, the LASzip VLR after
/// the other VLRs, the chunks (encoded `threads` at a time, the same bytes for any count) and
/// the chunk table before the EVLRs. LasReader reads it back; laz-perf and laz-rs decode the same
/// records except colours and extra bytes of points from several scanner channels (they differ
/// from LASzip's version 3 items there, see tests/io/las_writer_laz_test.cpp).
///
/// Legacy (32-bit) point counts are written as 0, as LAS 1.4 R15 requires for formats 6-10; the
/// global encoding has the WKT bit set, which those formats also require (other formats: only
/// when `vlrs` holds an OGC WKT record, LASF_Projection / 2112, see io/las_crs.hpp).
class LasWriter {
  public:
    /// Throws ConfigError listing every problem of `config`, OutputError if the file cannot be
    /// created.
    LasWriter(std::filesystem::path path, LasWriterConfig config);
    /// An encoder without a file: encode() and header_bytes() work, write(), write_block() and
    /// close() throw. For records placed in the file by someone else (a survey written by many
    /// MPI ranks at once). Throws ConfigError for a bad `config` or compression laz.
    explicit LasWriter(LasWriterConfig config);
    ~LasWriter();
    LasWriter(const LasWriter&) = delete;
    LasWriter& operator=(const LasWriter&) = delete;
    LasWriter(LasWriter&&) = delete;
    LasWriter& operator=(LasWriter&&) = delete;

    /// Appends points (any number per call).
    void write(std::span<const LasPoint> points);

    /// Encodes one point at the end of `block` without writing anything: const, so blocks can
    /// be encoded on many threads at once. Throws OutputError (naming the point's index in the
    /// block) for a point the file cannot hold; the writer is unaffected.
    void encode(const LasPoint& point, LasRecordBlock& block) const;
    void encode(const LasSimplePoint& point, LasRecordBlock& block) const;
    /// The same with the wave packet fields (formats 9, 10).
    void encode(const LasSimplePoint& point, const LasWavePacket& packet,
                LasRecordBlock& block) const;
    /// encode() of every point of `points` in order (the same bytes, bounds and counts), with
    /// the space made and the bounds kept once per call rather than per point. `Point` is
    /// LasSimplePoint or BlockPoint (io/point_sink.hpp), whose LasSimplePoint fields are encoded.
    template <class Point>
    void encode_points(std::span<const Point> points, LasRecordBlock& block) const;
    /// Byte offset of the wave packet fields in a record (formats 9, 10).
    [[nodiscard]] std::size_t wave_packet_field() const;
    /// Appends an encoded block (after any points given to write()).
    void write_block(const LasRecordBlock& block);
    /// Finalizes the header and commits the file. The writer accepts nothing afterwards.
    void close();
    /// close() for waveform_storage internal: `packets` (a file of the packets, back to back) is
    /// copied into the Waveform Data Packets EVLR, the first EVLR, right after the points.
    void close_with_waveform_data(const std::filesystem::path& packets);

    /// The header and VLRs, offset_to_point_data bytes, of a file whose records `totals` sums
    /// up (las_add_totals of its blocks: count, integer bounds, counts by return), as close()
    /// writes them. Throws ConfigError when the file would have EVLRs or is compressed.
    [[nodiscard]] std::vector<std::uint8_t> header_bytes(const LasRecordBlock& totals) const;

    /// Points accepted so far.
    [[nodiscard]] std::uint64_t point_count() const { return header_.point_count + chunk_points_; }
    /// The header; its point count, bounds and EVLR start are final only after close().
    [[nodiscard]] const LasHeader& header() const { return header_; }
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

  private:
    void set_up_header();
    static void append_vlr(const LasVlr& v, std::vector<std::uint8_t>& out);
    /// encode_header() and the VLRs (not the LASzip one).
    [[nodiscard]] std::vector<std::uint8_t> header_and_vlrs(const LasHeader& h) const;
    /// What encoding a record reads of the writer, copied into the encoding loop's locals: the
    /// records are stored through byte pointers, which may alias any member, so a member read
    /// in the loop was loaded again after every store.
    struct RecordConstants {
        double offset[3];
        double steps_per_unit[3];
        std::size_t record_length;
        int point_format;
    };
    [[nodiscard]] RecordConstants record_constants() const;
    void encode(const LasPoint& p, std::uint64_t index, std::uint8_t* record);
    void encode_record(const LasPoint& p, std::uint64_t index, std::uint8_t* record,
                       std::int32_t q[3]) const;
    // Hidden: not interposable in position-independent code, so encode_points() inlines them.
    [[gnu::visibility("hidden")]] void encode_record(const LasSimplePoint& p, std::uint64_t index,
                                                     std::uint8_t* record, std::int32_t q[3],
                                                     const RecordConstants& c) const;
    /// Bytes 0-29, the part every record has (flags: byte 15), after the checks.
    [[gnu::visibility("hidden")]] void encode_base(const LasSimplePoint& p, std::uint8_t flags,
                                                   std::uint64_t index, std::uint8_t* record,
                                                   std::int32_t q[3],
                                                   const RecordConstants& c) const;
    template <class Point>
    void encode_into(const Point& p, LasRecordBlock& block) const;
    void flush_chunk();
    void write_waveform_evlr();
    // compression laz (src/io/las_writer_laz.cpp); the plain path where there is no laz_.
    void open_laz();
    void start_laz_points();
    void append_records(const std::uint8_t* records, std::size_t count);
    /// Writes what is left of the points (laz: the last chunks and the table); returns where
    /// the point data ends.
    [[nodiscard]] std::uint64_t finish_points();
    void write_laz_table_offset();
    [[nodiscard]] std::array<std::uint8_t, 375> encode_header(const LasHeader& h) const;
    [[noreturn]] void fail(const std::string& what);

    std::filesystem::path path_;
    LasWriterConfig config_;
    LasHeader header_;
    double steps_per_unit_[3] = {1, 1, 1};  ///< 1 / header_.scale
    std::unique_ptr<AtomicFile> file_;
    std::unique_ptr<detail::DirectSink> sink_;  ///< header, VLRs and points, by large writes
    std::vector<std::uint8_t> chunk_;
    std::size_t chunk_points_ = 0;
    std::int32_t lo_[3] = {0, 0, 0};  ///< integer bounds of the points written so far
    std::int32_t hi_[3] = {0, 0, 0};
    std::filesystem::path waveform_data_;          ///< close_with_waveform_data's packets
    std::unique_ptr<LasVlr> laz_vlr_;              ///< compression laz: the LASzip VLR
    std::unique_ptr<detail::LazChunkWriter> laz_;  ///< compression laz: the chunks
    bool failed_ = false;
    bool closed_ = false;
};

}  // namespace beamtrace
