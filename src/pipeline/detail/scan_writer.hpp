// The writing half of `beamtrace scan`, fed while the scan is traced: the pieces of points.ply,
// range.npy and hits.csv whose rays are traced are encoded into their files (on the pool's
// threads, between two traced chunks, while the rays and hits are still in the caches) instead
// of in one pass after the trace; what needs every hit (range.png's colour span, points.laz's
// bounds) and the renames come at the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/mapped_file.hpp"
#include "beamtrace/pipeline/scan_job.hpp"
#include "core/created_dirs.hpp"

namespace beamtrace::detail {

/// Rays a piece of the writers' work covers: add()'s ranges start at multiples of it.
inline constexpr std::size_t kScanPieceRays = std::size_t{1} << 13;

class ScanParallelFile;

/// The outputs of one scan (config.outputs, in config.output_dir, created if missing), written
/// as its rays are traced. Construct it once the inputs are read (it creates the temporary
/// files), call add() for each traced range of rays in order, then finish(). Destroyed without
/// a successful finish() (an error, an interrupt), it leaves none of the outputs, nor the folder
/// when it created it.
///
/// points.ply is mapped at its largest size (every ray a point) with the header of that count;
/// finish() writes the true header, moves the records when the count has fewer digits, and
/// truncates the file. range.npy is mapped at its size; the columns of the range image whose
/// rays are all traced are filled by add(). The bytes are those of the plain writers at any
/// thread count and in any split of the rays into add() ranges.
class ScanStream {
  public:
    /// `hits` is read in the ranges given to add() (hit i of ray i); `width` x `height` is the
    /// range images' grid (pixel (v, u) of ray u * height + v), 0 x 0 none.
    ScanStream(const ScanJobConfig& config, const RayBatch& rays, const HitBatch& hits, int width,
               int height, ThreadPool& pool);
    ~ScanStream();
    ScanStream(const ScanStream&) = delete;
    ScanStream& operator=(const ScanStream&) = delete;

    /// Rays [begin, end) are traced: encodes their pieces. `begin` is the previous call's `end`
    /// (0 first) and a multiple of kScanPieceRays.
    void add(std::size_t begin, std::size_t end);
    /// Every ray is traced and added: writes the rest, renames the files into place.
    [[nodiscard]] ScanWritten finish();

  private:
    struct Piece;
    [[nodiscard]] bool image() const { return width_ > 0 && height_ > 0; }
    void open_ply();
    void open_range_image();
    void count_pieces(std::size_t first, std::size_t last);
    void encode_pieces(std::size_t first, std::size_t last);
    void fill_columns(std::size_t vb, std::size_t ve, std::size_t ub, std::size_t ue) const;
    void encode_ply_piece(std::size_t p) const;
    [[nodiscard]] std::size_t finish_ply();
    void write_csv();
    void run_final_tasks(std::vector<std::string>& notes);
    void commit_mapped_and_csv();
    void remove_committed() noexcept;

    const ScanJobConfig& config_;
    const RayBatch& rays_;
    const HitBatch& hits_;
    std::size_t width_, height_;
    ThreadPool& pool_;
    CreatedDirs created_;  ///< first: removed (when empty) after the files' own clean-up
    std::vector<Piece> pieces_;
    std::size_t added_ = 0;         ///< rays added so far
    std::size_t columns_done_ = 0;  ///< range image columns filled
    std::size_t points_ = 0;        ///< points.ply records encoded so far
    std::string ply_comment_;
    std::size_t ply_data_at_ = 0;  ///< where the records start (after the largest header)
    std::optional<MappedFile> ply_, npy_;
    std::unique_ptr<ScanParallelFile> csv_;
    float* range_ = nullptr;  ///< the range image, in npy_ or range_storage_
    std::unique_ptr<float[]> range_storage_;
    std::vector<std::filesystem::path> committed_;
};

}  // namespace beamtrace::detail
