#include "pipeline/detail/scan_writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string_view>
#include <system_error>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/hits_csv.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/io/point_sink_registry.hpp"

namespace beamtrace::detail {

/// A file that several threads write at once, each its own byte range (pwrite at known offsets,
/// no per-thread stream), appearing complete or not at all (AtomicFile: temporary file + rename;
/// destroyed uncommitted, it leaves nothing).
class ScanParallelFile {
  public:
    explicit ScanParallelFile(const std::filesystem::path& path)
        : file_(path), fd_(::fileno(file_.stream())) {}
    /// Writes `bytes` at `offset`; any thread, ranges that do not overlap.
    void write_at(std::string_view bytes, std::uint64_t offset) const {
        while (!bytes.empty()) {
            const ssize_t n = ::pwrite(fd_, bytes.data(), bytes.size(), static_cast<off_t>(offset));
            if (n < 0 && errno == EINTR) {
                continue;
            }
            if (n <= 0) {
                throw OutputError(file_.path().string() +
                                  ": write failed: " + std::strerror(n < 0 ? errno : EIO));
            }
            bytes.remove_prefix(static_cast<std::size_t>(n));
            offset += static_cast<std::uint64_t>(n);
        }
    }
    void commit() { file_.commit(); }
    [[nodiscard]] const std::filesystem::path& path() const { return file_.path(); }

  private:
    AtomicFile file_;
    int fd_;
};

/// The counts of a piece of kScanPieceRays rays, and its hits.csv rows.
struct ScanStream::Piece {
    std::size_t hits = 0;
    std::size_t kept = 0;    ///< hits not on excluded faces: points.ply's records
    std::size_t ply_at = 0;  ///< the records before this piece's
    std::string csv;         ///< its rows of hits.csv
};

namespace {

/// Rows of the range image a task fills (of the columns one add() completes).
constexpr std::size_t kBandRows = 64;

void prepare_output_dir(const std::filesystem::path& dir) {
    std::error_code ec;
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
        throw OutputError(dir.string() + ": output path exists and is not a directory");
    }
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        throw OutputError(dir.string() + ": cannot create output directory: " + ec.message());
    }
}

/// The points of hits [b, e) (ray index as the pulse index); with `exclude`, none on those
/// faces.
void scan_points(const RayBatch& rays, const HitBatch& hits, std::size_t b, std::size_t e,
                 const std::vector<FaceRange>* exclude, PointBlock& block) {
    block.clear();
    for (std::size_t i = b; i < e; ++i) {
        if (!hits.hit(i) || (exclude != nullptr && in_ranges(*exclude, hits.face[i]))) {
            continue;
        }
        const double t = hits.t[i];
        BlockPoint p;
        p.x = rays.ox[i] + t * rays.dx[i];
        p.y = rays.oy[i] + t * rays.dy[i];
        p.z = rays.oz[i] + t * rays.dz[i];
        p.range_m = hits.t[i];
        p.face = hits.face[i];
        p.pulse = i;
        block.points.push_back(p);
    }
}

constexpr std::size_t kLazBlock = std::size_t{1} << 16;

/// points.laz (ScanJobConfig::laz) of the hits kept for points.ply, around their bounds.
std::unique_ptr<PointSink> scan_laz_sink(const ScanJobConfig& config, const RayBatch& rays,
                                         const HitBatch& hits) {
    SinkFacts facts;
    facts.output_dir = config.output_dir;
    facts.provenance = "# beamtrace " BEAMTRACE_VERSION " scan";
    PointBlock block;
    bool any = false;
    for (std::size_t b = 0; b < rays.size(); b += kLazBlock) {
        scan_points(rays, hits, b, std::min(rays.size(), b + kLazBlock), &config.exclude_faces,
                    block);
        for (const BlockPoint& p : block.points) {
            const Vec3d v(p.x, p.y, p.z);
            for (std::size_t k = 0; k < 3; ++k) {
                facts.lo_m[k] = any ? std::min(facts.lo_m[k], v[k]) : v[k];
                facts.hi_m[k] = any ? std::max(facts.hi_m[k], v[k]) : v[k];
            }
            any = true;
        }
    }
    return point_sink("laz").make(facts);
}

/// Streams the points of `hits` (without the excluded faces) to one sink, checking config.cancel
/// between blocks; commits it. The points are LAS returns (one return per ray).
std::vector<std::filesystem::path> write_scan_laz(const ScanJobConfig& config, const RayBatch& rays,
                                                  const HitBatch& hits) {
    const std::unique_ptr<PointSink> sink = scan_laz_sink(config, rays, hits);
    PointBlock block;
    const auto buffer = sink->make_buffer();
    for (std::size_t b = 0; b < rays.size(); b += kLazBlock) {
        throw_if_cancelled(config.cancel, "scan");
        scan_points(rays, hits, b, std::min(rays.size(), b + kLazBlock), &config.exclude_faces,
                    block);
        for (BlockPoint& p : block.points) {
            p.return_number = p.number_of_returns = 1;
        }
        buffer->clear();
        sink->encode(block, *buffer);
        sink->write(*buffer);
    }
    throw_if_cancelled(config.cancel, "scan");
    return sink->commit();
}

}  // namespace

ScanStream::ScanStream(const ScanJobConfig& config, const RayBatch& rays, const HitBatch& hits,
                       int width, int height, ThreadPool& pool)
    : config_(config),
      rays_(rays),
      hits_(hits),
      width_(static_cast<std::size_t>(std::max(width, 0))),
      height_(static_cast<std::size_t>(std::max(height, 0))),
      pool_(pool),
      created_(config.output_dir),
      pieces_((rays.size() + kScanPieceRays - 1) / kScanPieceRays) {
    assert(hits.size() == rays.size());
    assert(!image() || width_ * height_ == rays.size());
    prepare_output_dir(config.output_dir);
    const ScanOutputs& o = config.outputs;
    if ((o.npy || o.png) && image()) {
        open_range_image();
    }
    if (o.csv) {
        csv_ = std::make_unique<ScanParallelFile>(config.output_dir / "hits.csv");
        csv_->write_at(kHitsCsvHeader, 0);
    }
    if (o.ply) {
        open_ply();
    }
}

ScanStream::~ScanStream() = default;

/// The range image (row-major, width x height metres, misses 0): straight into range.npy after
/// its header, or into memory of its own for range.png alone.
void ScanStream::open_range_image() {
    if (!config_.outputs.npy) {
        range_storage_ = std::make_unique_for_overwrite<float[]>(width_ * height_);
        range_ = range_storage_.get();
        return;
    }
    const std::string header = npy_f32_header(height_, width_);
    npy_.emplace(config_.output_dir / "range.npy",
                 header.size() + width_ * height_ * sizeof(float));
    const std::span<char> bytes = npy_->bytes();
    std::memcpy(bytes.data(), header.data(), header.size());
    // The header is 64-byte padded: the floats are aligned.
    range_ = reinterpret_cast<float*>(bytes.data() + header.size());
}

/// points.ply at its largest size: the header of one point a ray, then room for every record.
void ScanStream::open_ply() {
    ply_comment_ = "generated by beamtrace " BEAMTRACE_VERSION " scan (backend " +
                   std::string(to_string(config_.backend)) + ")";
    ply_data_at_ = points_ply_header(rays_.size(), ply_comment_).size();
    ply_.emplace(config_.output_dir / "points.ply", ply_data_at_ + rays_.size() * kPlyRecordBytes);
}

void ScanStream::add(std::size_t begin, std::size_t end) {
    assert(begin == added_ && begin % kScanPieceRays == 0);
    assert(end <= rays_.size() && (end % kScanPieceRays == 0 || end == rays_.size()));
    if (end <= begin) {
        return;
    }
    const std::size_t first = begin / kScanPieceRays;
    const std::size_t last = (end + kScanPieceRays - 1) / kScanPieceRays;
    count_pieces(first, last);
    for (std::size_t p = first; p < last; ++p) {
        pieces_[p].ply_at = points_;
        points_ += pieces_[p].kept;
    }
    added_ = end;
    encode_pieces(first, last);
}

/// Counts the hits and points of pieces [first, last) and formats their hits.csv rows.
void ScanStream::count_pieces(std::size_t first, std::size_t last) {
    const std::vector<FaceRange>& exclude = config_.exclude_faces;
    pool_.parallel_for(last - first, 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t p = first + b; p < first + e; ++p) {
            Piece& piece = pieces_[p];
            const std::size_t end = std::min(rays_.size(), (p + 1) * kScanPieceRays);
            std::size_t hit = 0, kept = 0;
            for (std::size_t i = p * kScanPieceRays; i < end; ++i) {
                if (hits_.hit(i)) {
                    ++hit;
                    kept += exclude.empty() || !in_ranges(exclude, hits_.face[i]) ? 1 : 0;
                }
            }
            piece.hits = hit;
            piece.kept = kept;
            if (csv_) {
                append_hits_csv_rows(hits_, p * kScanPieceRays, end, piece.csv);
            }
        }
    });
}

/// Encodes the points.ply records of pieces [first, last), and fills the range image's columns
/// that are complete now (bands of rows), on the pool's threads.
void ScanStream::encode_pieces(std::size_t first, std::size_t last) {
    const std::size_t ply_tasks = ply_ ? last - first : 0;
    const std::size_t ub = columns_done_;
    const std::size_t ue = range_ != nullptr ? added_ / height_ : ub;
    const std::size_t bands = ue > ub ? (height_ + kBandRows - 1) / kBandRows : 0;
    pool_.parallel_for(ply_tasks + bands, 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            if (k < ply_tasks) {
                encode_ply_piece(first + k);
            } else {
                const std::size_t vb = (k - ply_tasks) * kBandRows;
                fill_columns(vb, std::min(height_, vb + kBandRows), ub, ue);
            }
        }
    });
    columns_done_ = ue;
}

/// Range image pixels (v, u) for rows [vb, ve) of columns [ub, ue): down each column the rays
/// are consecutive, along each row the pixels; a band of rows keeps both within a few lines.
void ScanStream::fill_columns(std::size_t vb, std::size_t ve, std::size_t ub,
                              std::size_t ue) const {
    for (std::size_t u = ub; u < ue; ++u) {
        for (std::size_t v = vb, i = u * height_ + vb; v < ve; ++v, ++i) {
            range_[v * width_ + u] = hits_.hit(i) ? hits_.t[i] : 0.0f;
        }
    }
}

/// Encodes the points of piece `p` (without the excluded faces) as points.ply records at their
/// place.
void ScanStream::encode_ply_piece(std::size_t p) const {
    const Piece& piece = pieces_[p];
    if (piece.kept == 0) {
        return;
    }
    const std::size_t at = ply_data_at_ + piece.ply_at * kPlyRecordBytes;
    // One fault-in for the piece's pages (a hint): 1.03-1.06x the end-to-end rate at one thread
    // when the records were encoded after the trace (A/B, Intel Xeon).
    ply_->prefault(at, piece.kept * kPlyRecordBytes);
    char* out = ply_->bytes().data() + at;
    const std::vector<FaceRange>& exclude = config_.exclude_faces;
    const std::size_t end = std::min(rays_.size(), (p + 1) * kScanPieceRays);
    for (std::size_t i = p * kScanPieceRays; i < end; ++i) {
        if (!hits_.hit(i) || (!exclude.empty() && in_ranges(exclude, hits_.face[i]))) {
            continue;
        }
        const double t = hits_.t[i];  // as scan_points places the points
        out = encode_ply_record(rays_.ox[i] + t * rays_.dx[i], rays_.oy[i] + t * rays_.dy[i],
                                rays_.oz[i] + t * rays_.dz[i], hits_.t[i], hits_.face[i],
                                static_cast<std::uint32_t>(i), out);
    }
    assert(out == ply_->bytes().data() + at + piece.kept * kPlyRecordBytes);
}

/// Writes points.ply's header for the points encoded; when their count has fewer digits than
/// the rays', moves the records up to it. Returns the file's size.
std::size_t ScanStream::finish_ply() {
    const std::string header = points_ply_header(points_, ply_comment_);
    assert(header.size() <= ply_data_at_);
    char* const data = ply_->bytes().data();
    if (header.size() != ply_data_at_) {
        std::memmove(data + header.size(), data + ply_data_at_, points_ * kPlyRecordBytes);
    }
    std::memcpy(data, header.data(), header.size());
    return header.size() + points_ * kPlyRecordBytes;
}

/// hits.csv's rows are formatted; their offsets are known now.
void ScanStream::write_csv() {
    std::vector<std::uint64_t> at(pieces_.size() + 1, kHitsCsvHeader.size());
    for (std::size_t p = 0; p < pieces_.size(); ++p) {
        at[p + 1] = at[p] + pieces_[p].csv.size();
    }
    pool_.parallel_for(pieces_.size(), 8, [&](std::size_t b, std::size_t e) {
        throw_if_cancelled(config_.cancel, "scan");
        for (std::size_t p = b; p < e; ++p) {
            csv_->write_at(pieces_[p].csv, at[p]);
        }
    });
}

/// range.png and points.laz (each one task, on the pool's threads), committed when done; their
/// files in committed_, range.png's summary line in `notes`.
void ScanStream::run_final_tasks(std::vector<std::string>& notes) {
    const bool png = config_.outputs.png && image(), laz = config_.outputs.laz;
    const std::size_t tasks = (laz ? 1 : 0) + (png ? 1 : 0);  // points.laz first: the longest
    std::mutex mutex;
    pool_.parallel_for(tasks, 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            throw_if_cancelled(config_.cancel, "scan");
            std::vector<std::filesystem::path> files;
            std::string note;
            if (laz && k == 0) {
                files = write_scan_laz(config_, rays_, hits_);
            } else {
                files.push_back(config_.output_dir / "range.png");
                note = write_range_png(files.back(), {range_, width_ * height_},
                                       static_cast<int>(width_), static_cast<int>(height_));
            }
            const std::lock_guard lock(mutex);
            committed_.insert(committed_.end(), files.begin(), files.end());
            if (!note.empty()) {
                notes.push_back(std::move(note));
            }
        }
    });
}

ScanWritten ScanStream::finish() {
    assert(added_ == rays_.size());
    ScanWritten written;
    std::size_t kept = 0;
    for (const Piece& p : pieces_) {
        written.hits += p.hits;
        kept += p.kept;
    }
    written.points_written = config_.outputs.ply || config_.outputs.laz ? kept : 0;
    try {
        run_final_tasks(written.notes);
        if (csv_) {
            write_csv();
        }
        throw_if_cancelled(config_.cancel, "scan");
        commit_mapped_and_csv();
    } catch (...) {
        remove_committed();
        throw;
    }
    created_.keep();
    for (const std::string_view name :  // ply, npy, png, csv, laz
         {"points.ply", "range.npy", "range.png", "hits.csv", "points.laz"}) {
        for (const auto& f : committed_) {
            if (f.filename() == name) {
                written.outputs.push_back(f);
            }
        }
    }
    return written;
}

/// Renames points.ply (its header written, cut to its size), range.npy and hits.csv into place,
/// each on a thread of the pool: the unmapping, and the eviction of a previous run's file that
/// the rename replaces (20 ms for a points.ply of 85 MB), overlap.
void ScanStream::commit_mapped_and_csv() {
    std::mutex mutex;
    pool_.parallel_for(3, 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            std::filesystem::path done;
            if (k == 0 && ply_) {
                ply_->commit(finish_ply());
                done = ply_->path();
            } else if (k == 1 && npy_) {
                npy_->commit();
                done = npy_->path();
            } else if (k == 2 && csv_) {
                csv_->commit();
                done = csv_->path();
            }
            if (!done.empty()) {
                const std::lock_guard lock(mutex);
                committed_.push_back(std::move(done));
            }
        }
    });
}

/// After a failure: removes the outputs already renamed into place.
void ScanStream::remove_committed() noexcept {
    for (const auto& f : committed_) {
        std::error_code ignored;
        std::filesystem::remove(f, ignored);
    }
}

}  // namespace beamtrace::detail
