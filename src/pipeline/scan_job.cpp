#include "beamtrace/pipeline/scan_job.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <system_error>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/name_table.hpp"
#include "beamtrace/io/hits_csv.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/io/parallel_file.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/io/point_sink_registry.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/sensor/rays_file.hpp"
#include "core/created_dirs.hpp"
#include "pipeline/detail/survey_diagnosis.hpp"

namespace beamtrace {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr std::size_t kTraceChunk = std::size_t{1} << 16;

/// The outputs of ScanOutputs by name, in the order they are listed and written.
struct ScanOutputName {
    std::string_view name;
    bool ScanOutputs::*on;
};
constexpr std::array<ScanOutputName, 5> kScanOutputs{{{"ply", &ScanOutputs::ply},
                                                      {"npy", &ScanOutputs::npy},
                                                      {"png", &ScanOutputs::png},
                                                      {"csv", &ScanOutputs::csv},
                                                      {"laz", &ScanOutputs::laz}}};

std::string scan_output_names(std::string_view separator, std::string_view last) {
    std::string out;
    for (std::size_t k = 0; k < kScanOutputs.size(); ++k) {
        out += k == 0 ? "" : (k + 1 == kScanOutputs.size() ? last : separator);
        out += kScanOutputs[k].name;
    }
    return out;
}

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

/// points.laz (ScanJobConfig::laz) of the hits kept for points.ply, around their bounds.
std::unique_ptr<PointSink> scan_laz_sink(const ScanJobConfig& config, const RayBatch& rays,
                                         const HitBatch& hits) {
    SinkFacts facts;
    facts.output_dir = config.output_dir;
    facts.provenance = "# beamtrace " BEAMTRACE_VERSION " scan";
    PointBlock block;
    bool any = false;
    for (std::size_t b = 0; b < rays.size(); b += kTraceChunk) {
        scan_points(rays, hits, b, std::min(rays.size(), b + kTraceChunk), &config.exclude_faces,
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
/// between chunks; commits it. The points are LAS returns (one return per ray).
std::vector<std::filesystem::path> write_scan_laz(const ScanJobConfig& config, const RayBatch& rays,
                                                  const HitBatch& hits) {
    const std::unique_ptr<PointSink> sink = scan_laz_sink(config, rays, hits);
    PointBlock block;
    const auto buffer = sink->make_buffer();
    for (std::size_t b = 0; b < rays.size(); b += kTraceChunk) {
        throw_if_cancelled(config.cancel, "scan");
        scan_points(rays, hits, b, std::min(rays.size(), b + kTraceChunk), &config.exclude_faces,
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

/// The counts of every chunk of kTraceChunk rays: what the writers need before they lay out
/// their files.
struct ScanTally {
    std::vector<std::size_t> hits;  ///< per chunk
    std::vector<std::size_t> kept;  ///< per chunk: hits not on excluded faces (points.ply)
};

/// Rows [vb, ve) (at most kTile) of the range image of `hits` (w x h, ray u * h + v at pixel
/// (v, u), misses 0) into `band` (row-major). Tiles of kTile x kTile pixels: each column's rays
/// are read in a row of the tile, then each image row's pixels are stored together (storing a
/// column at a time, kTile rows 1.5 pages apart share two cache sets and evict each other).
void range_band(const HitBatch& hits, std::size_t w, std::size_t h, std::size_t vb, std::size_t ve,
                float* band) {
    constexpr std::size_t kTile = 16;
    const std::size_t rows = ve - vb;
    assert(rows <= kTile);
    const float* const t = hits.t.data();
    const std::uint32_t* const face = hits.face.data();
    alignas(64) float tile[kTile][kTile];  // [column][row]
    for (std::size_t u0 = 0; u0 < w; u0 += kTile) {
        const std::size_t columns = std::min(kTile, w - u0);
        for (std::size_t c = 0; c < columns; ++c) {
            const std::size_t i = (u0 + c) * h + vb;
            const float* const tc = t + i;
            const std::uint32_t* const fc = face + i;
            for (std::size_t r = 0; r < rows; ++r) {
                tile[c][r] = fc[r] != kNoFace ? tc[r] : 0.0f;
            }
        }
        for (std::size_t r = 0; r < rows; ++r) {
            float* const row = band + r * w + u0;
            for (std::size_t c = 0; c < columns; ++c) {
                row[c] = tile[c][r];
            }
        }
    }
}

/// The range image of `hits` (row-major w x h metres, misses 0): pixel (v, u) is ray u * h + v.
/// Bands of kBand rows on the pool's threads. Each band is made in `image` when given (else in a
/// buffer of the thread's, reused band after band) and, with `npy`, written there at `npy_at` +
/// its offset.
void range_image(const HitBatch& hits, std::size_t w, std::size_t h, ThreadPool& pool, float* image,
                 const ParallelFile* npy, std::uint64_t npy_at) {
    constexpr std::size_t kBand = 16;  // range_band's rows at most
    pool.parallel_for(h, kBand, [&](std::size_t b, std::size_t e) {
        // A pool of one thread passes every row at once.
        const std::unique_ptr<float[]> buffer =
            image != nullptr ? nullptr : std::make_unique_for_overwrite<float[]>(kBand * w);
        for (std::size_t vb = b; vb < e; vb += kBand) {
            const std::size_t ve = std::min(e, vb + kBand);
            float* band = image != nullptr ? image + vb * w : buffer.get();
            range_band(hits, w, h, vb, ve, band);
            if (npy != nullptr) {
                npy->write_at({reinterpret_cast<const char*>(band), (ve - vb) * w * sizeof(float)},
                              npy_at + vb * w * sizeof(float));
            }
        }
    });
}

/// Counts each chunk's hits and points (chunks on the pool's threads).
ScanTally tally_scan(const ScanJobConfig& config, const HitBatch& hits, ThreadPool& pool) {
    const std::size_t n = hits.size();
    const std::size_t chunks = (n + kTraceChunk - 1) / kTraceChunk;
    ScanTally tally{std::vector<std::size_t>(chunks), std::vector<std::size_t>(chunks)};
    const std::vector<FaceRange>& exclude = config.exclude_faces;
    pool.parallel_for(chunks, 1, [&](std::size_t cb, std::size_t ce) {
        for (std::size_t c = cb; c < ce; ++c) {
            std::size_t hit = 0, kept = 0;
            for (std::size_t i = c * kTraceChunk; i < std::min(n, (c + 1) * kTraceChunk); ++i) {
                if (hits.hit(i)) {
                    ++hit;
                    kept += exclude.empty() || !in_ranges(exclude, hits.face[i]) ? 1 : 0;
                }
            }
            tally.hits[c] = hit;
            tally.kept[c] = kept;
        }
    });
    return tally;
}

/// Writes the points of chunk `c` (rays [c, c + 1) x kTraceChunk, without the excluded faces)
/// as points.ply records to `out`.
void write_ply_chunk(const ScanJobConfig& config, const RayBatch& rays, const HitBatch& hits,
                     std::size_t c, StagedRange& out) {
    const std::vector<FaceRange>& exclude = config.exclude_faces;
    const std::size_t end = std::min(rays.size(), (c + 1) * kTraceChunk);
    char* at = out.begin();
    char* limit = out.limit();
    static_assert(kPlyRecordBytes <= StagedRange::kSlack);
    for (std::size_t i = c * kTraceChunk; i < end; ++i) {
        if (!hits.hit(i) || (!exclude.empty() && in_ranges(exclude, hits.face[i]))) {
            continue;
        }
        const double t = hits.t[i];  // as scan_points places the points
        at = encode_ply_record(rays.ox[i] + t * rays.dx[i], rays.oy[i] + t * rays.dy[i],
                               rays.oz[i] + t * rays.dz[i], hits.t[i], hits.face[i],
                               static_cast<std::uint32_t>(i), at);
        if (at >= limit) {
            at = out.flush(at);
            limit = out.limit();
        }
    }
    out.finish(at);
}

/// The outputs of one scan being written. points.ply and range.npy are mapped files (their
/// sizes are known from the tally) that the pool's threads fill in place, points.ply a chunk of
/// rays each; hits.csv is written by several threads at once at offsets known once its rows are
/// formatted. These three are renamed into place once all succeeded; range.png and points.laz
/// are each one task, committed when done. Destroyed after a failure, it leaves none of them
/// (remove_committed() for those already renamed).
class ScanWriter {
  public:
    ScanWriter(const ScanJobConfig& config, const RayBatch& rays, const HitBatch& hits, int width,
               int height, ScanTally tally)
        : config_(config),
          rays_(rays),
          hits_(hits),
          width_(width),
          height_(height),
          tally_(std::move(tally)) {}

    /// Writes every output on the pool's threads; returns them in the order ply, npy, png,
    /// csv, laz, and range.png's summary line in `notes`.
    std::vector<std::filesystem::path> run(ThreadPool& pool, std::vector<std::string>& notes) {
        open_files(pool);
        pool.parallel_for(tasks_.size(), 1, [&](std::size_t b, std::size_t e) {
            for (std::size_t k = b; k < e; ++k) {
                throw_if_cancelled(config_.cancel, "scan");
                run_task(tasks_[k]);
            }
        });
        if (csv_) {
            write_csv(pool);
        }
        throw_if_cancelled(config_.cancel, "scan");
        std::vector<std::filesystem::path> files;
        commit(ply_, files);
        commit(npy_, files);
        append_done(files, "range.png");
        commit(csv_, files);
        append_done(files, "points.laz");
        notes = notes_;
        return files;
    }

    /// After a failure: removes the outputs already renamed into place.
    void remove_committed() noexcept {
        for (const auto& f : committed_) {
            std::error_code ignored;
            std::filesystem::remove(f, ignored);
        }
    }

  private:
    enum class Kind { laz, png, ply, csv };
    struct Task {
        Kind kind;
        std::size_t chunk = 0;
    };

    [[nodiscard]] bool image() const { return width_ > 0 && height_ > 0; }

    /// Opens the files written in parallel (with their headers), makes the range image (in
    /// range.npy's mapping when it is written) and lists the tasks, the longest first.
    void open_files(ThreadPool& pool) {
        const ScanOutputs& o = config_.outputs;
        const std::size_t chunks = tally_.kept.size();
        if (o.laz) {
            tasks_.push_back({Kind::laz});
        }
        if ((o.npy || o.png) && image()) {
            make_range_image(pool);
        }
        if (o.png && image()) {
            tasks_.push_back({Kind::png});
        }
        if (o.csv) {
            csv_.emplace(config_.output_dir / "hits.csv");
            csv_->write_at(kHitsCsvHeader, 0);
            csv_rows_.resize(chunks);
            for (std::size_t c = 0; c < chunks; ++c) {
                tasks_.push_back({Kind::csv, c});
            }
        }
        if (o.ply) {
            open_ply();
        }
    }

    /// The range image (row-major, width x height metres, misses 0): written to range.npy
    /// band by band, and kept in memory of its own for range.png.
    void make_range_image(ThreadPool& pool) {
        const auto w = static_cast<std::size_t>(width_), h = static_cast<std::size_t>(height_);
        std::uint64_t at = 0;
        if (config_.outputs.npy) {
            const std::string header = npy_f32_header(h, w);
            npy_.emplace(config_.output_dir / "range.npy", header.size() + w * h * sizeof(float));
            npy_->write_at(header, 0);
            at = header.size();
        }
        if (config_.outputs.png) {
            range_storage_ = std::make_unique_for_overwrite<float[]>(w * h);
            range_ = std::span<const float>(range_storage_.get(), w * h);
        }
        range_image(hits_, w, h, pool, range_storage_.get(), npy_ ? &*npy_ : nullptr, at);
    }

    void open_ply() {
        const std::string comment = "generated by beamtrace " BEAMTRACE_VERSION " scan (backend " +
                                    std::string(to_string(config_.backend)) + ")";
        std::size_t points = 0;
        for (const std::size_t k : tally_.kept) {
            points += k;
        }
        const std::string header = points_ply_header(points, comment);
        ply_.emplace(config_.output_dir / "points.ply", header.size() + points * kPlyRecordBytes);
        ply_->write_at(header, 0);
        ply_at_.assign(1, header.size());
        for (std::size_t c = 0; c < tally_.kept.size(); ++c) {
            ply_at_.push_back(ply_at_.back() + tally_.kept[c] * kPlyRecordBytes);
            tasks_.push_back({Kind::ply, c});
        }
    }

    void run_task(const Task& t) {
        switch (t.kind) {
            case Kind::laz:
                done(write_scan_laz(config_, rays_, hits_), {});
                break;
            case Kind::png: {
                const auto path = config_.output_dir / "range.png";
                std::string note = write_range_png(path, range_, width_, height_);
                done({path}, std::move(note));
                break;
            }
            case Kind::ply: {
                StagedRange out(*ply_, ply_at_[t.chunk]);
                write_ply_chunk(config_, rays_, hits_, t.chunk, out);
                break;
            }
            case Kind::csv:
                append_hits_csv_rows(hits_, t.chunk * kTraceChunk,
                                     std::min(hits_.size(), (t.chunk + 1) * kTraceChunk),
                                     csv_rows_[t.chunk]);
                break;
        }
    }

    /// hits.csv's rows are formatted; their offsets are known now.
    void write_csv(ThreadPool& pool) {
        std::vector<std::uint64_t> at(csv_rows_.size() + 1, kHitsCsvHeader.size());
        for (std::size_t c = 0; c < csv_rows_.size(); ++c) {
            at[c + 1] = at[c] + csv_rows_[c].size();
        }
        pool.parallel_for(csv_rows_.size(), 1, [&](std::size_t b, std::size_t e) {
            for (std::size_t c = b; c < e; ++c) {
                throw_if_cancelled(config_.cancel, "scan");
                csv_->write_at(csv_rows_[c], at[c]);
            }
        });
    }

    /// A task's files are in place (and its summary line).
    void done(std::vector<std::filesystem::path> files, std::string note) {
        const std::lock_guard lock(mutex_);
        committed_.insert(committed_.end(), files.begin(), files.end());
        if (!note.empty()) {
            notes_.push_back(std::move(note));
        }
    }

    template <typename File>
    void commit(std::optional<File>& f, std::vector<std::filesystem::path>& files) {
        if (f) {
            f->commit();
            committed_.push_back(f->path());
            files.push_back(f->path());
        }
    }

    /// Lists the committed file named `name`, if any.
    void append_done(std::vector<std::filesystem::path>& files, std::string_view name) const {
        for (const auto& f : committed_) {
            if (f.filename() == name) {
                files.push_back(f);
            }
        }
    }

    const ScanJobConfig& config_;
    const RayBatch& rays_;
    const HitBatch& hits_;
    int width_, height_;
    ScanTally tally_;
    std::vector<Task> tasks_;
    std::optional<ParallelFile> ply_, npy_, csv_;
    std::vector<std::uint64_t> ply_at_;  ///< per chunk: offset of its first record, then the end
    std::span<const float> range_;       ///< the range image for range.png, in range_storage_
    std::unique_ptr<float[]> range_storage_;
    std::vector<std::string> csv_rows_;  ///< per chunk: its formatted rows
    std::mutex mutex_;                   ///< guards committed_ and notes_ during the tasks
    std::vector<std::filesystem::path> committed_;
    std::vector<std::string> notes_;
};

/// The scan's rays, and the range image's width x height (0 x 0: none).
RayBatch cast_scan_rays(const ScanJobConfig& config, int& width, int& height) {
    StaticRays cast =
        static_scan_pattern(config.pattern).static_rays({config.sensor, config.rays_file});
    if (!cast.grid && config.image_width) {
        cast.grid = ImageGrid{*config.image_width, *config.image_height};
        if (static_cast<std::size_t>(cast.grid->width) *
                static_cast<std::size_t>(cast.grid->height) !=
            cast.rays.size()) {
            throw ConfigError(
                config.rays_file.string() + ": has " + std::to_string(cast.rays.size()) +
                " rays but --width x --height is " + std::to_string(cast.grid->width) + " x " +
                std::to_string(cast.grid->height));
        }
    }
    width = cast.grid ? cast.grid->width : 0;
    height = cast.grid ? cast.grid->height : 0;
    return std::move(cast.rays);
}

}  // namespace

ScanOutputs parse_scan_outputs(std::string_view list) {
    const std::string expected =
        " (expected a comma-separated list of " + scan_output_names(", ", " and ") + ")";
    ScanOutputs o{false, false, false, false, false};
    bool any = false;
    while (true) {
        const std::size_t comma = std::min(list.find(','), list.size());
        const std::string_view item = list.substr(0, comma);
        const auto* e = std::find_if(kScanOutputs.begin(), kScanOutputs.end(),
                                     [&](const ScanOutputName& n) { return n.name == item; });
        if (item.empty()) {
            throw ConfigError("empty output name" + expected);
        }
        if (e == kScanOutputs.end()) {
            throw ConfigError("unknown output '" + std::string(item) + "'" + expected);
        }
        if (o.*(e->on)) {
            throw ConfigError("output '" + std::string(item) + "' is listed twice");
        }
        o.*(e->on) = any = true;
        if (comma == list.size()) {
            break;
        }
        list.remove_prefix(comma + 1);
    }
    return o;
}

std::string to_string(const ScanOutputs& outputs) {
    std::string out;
    for (const ScanOutputName& n : kScanOutputs) {
        if (outputs.*(n.on)) {
            out += (out.empty() ? "" : ",") + std::string(n.name);
        }
    }
    return out;
}

std::string scan_output_choices() {
    return scan_output_names(", ", ", ");
}

std::string parse_pattern_kind(std::string_view name) {
    return std::string(static_scan_pattern(name).name);
}

KdTreeBuildConfig parse_kdtree_rules(std::string_view name) {
    static constexpr NameTable<KdSplitRule, 2> kRules{
        "k-d tree rule set", {{{KdSplitRule::sah, "sah"}, {KdSplitRule::report, "report"}}}};
    return kRules.parse(name) == KdSplitRule::report ? KdTreeBuildConfig::report()
                                                     : KdTreeBuildConfig{};
}

void ScanJobConfig::apply(const ScanSensorOptions& o) {
    if (demo) {
        sensor = demo_sensor();
    }
    sensor.position_m = o.position_m.value_or(sensor.position_m);
    if (o.orientation_rad) {
        sensor.orientation = {o.orientation_rad->x, o.orientation_rad->y, o.orientation_rad->z};
    }
    if (reads_rays_file()) {
        image_width = o.width;
        image_height = o.height;
    } else {
        sensor.width = o.width.value_or(sensor.width);
        sensor.height = o.height.value_or(sensor.height);
    }
    sensor.hfov_rad = o.hfov_rad.value_or(sensor.hfov_rad);
    sensor.vfov_rad = o.vfov_rad.value_or(sensor.vfov_rad);
}

bool ScanJobConfig::reads_rays_file() const {
    const ScanPatternEntry* e = find_scan_pattern(pattern);
    return e != nullptr && e->reads_rays_file;
}

std::vector<std::string> ScanJobConfig::validate() const {
    std::vector<std::string> p;
    if (demo && !meshes.empty()) {
        p.emplace_back("--demo and --mesh are exclusive");
    }
    if (!demo && meshes.empty()) {
        p.emplace_back("no scene: give --mesh FILE (repeatable) or --demo");
    }
    if (output_dir.empty()) {
        p.emplace_back("no output directory (--output DIR)");
    }
    if (to_string(outputs).empty()) {
        p.emplace_back("no output selected (--outputs: " + scan_output_choices() + ")");
    }
    const ScanPatternEntry* e = find_scan_pattern(pattern);
    if (e == nullptr || e->static_rays == nullptr) {
        p.emplace_back("unknown pattern '" + pattern + "' (expected " +
                       static_scan_pattern_choices() + ")");
        return p;
    }
    if (e->reads_rays_file) {
        if (rays_file.empty()) {
            p.emplace_back("--pattern " + pattern + " needs --rays FILE");
        }
        if (image_width.has_value() != image_height.has_value()) {
            p.emplace_back("--width and --height go together");
        } else if (image_width && (*image_width < 1 || *image_height < 1)) {
            p.emplace_back("--width and --height must be at least 1");
        }
    } else if (!rays_file.empty()) {
        p.emplace_back("--rays needs --pattern rays");
    }
    if (e->check_static != nullptr) {
        for (auto& s : e->check_static({sensor, rays_file})) {
            p.push_back(std::move(s));
        }
    }
    return p;
}

ScanWritten write_scan_outputs(const ScanJobConfig& config, const RayBatch& rays,
                               const HitBatch& hits, int width, int height, ThreadPool& pool) {
    CreatedDirs created(config.output_dir);  // removed if empty on an error or interrupt
    prepare_output_dir(config.output_dir);
    ScanWritten written;
    ScanTally tally = tally_scan(config, hits, pool);
    std::size_t kept = 0;
    for (std::size_t c = 0; c < tally.hits.size(); ++c) {
        written.hits += tally.hits[c];
        kept += tally.kept[c];
    }
    written.points_written = config.outputs.ply || config.outputs.laz ? kept : 0;
    ScanWriter writer(config, rays, hits, width, height, std::move(tally));
    try {
        written.outputs = writer.run(pool, written.notes);
    } catch (...) {
        writer.remove_committed();
        throw;
    }
    created.keep();
    return written;
}

ScanResult run_scan(const ScanJobConfig& config, const ProgressFn& progress) {
    const auto problems = config.validate();
    if (!problems.empty()) {
        std::string msg;
        for (const auto& s : problems) {
            msg += (msg.empty() ? "" : "; ") + s;
        }
        throw ConfigError(msg);
    }
    throw_if_cancelled(config.cancel, "scan");
    ScanResult result;
    ThreadPool pool(config.threads);

    // Inputs first: nothing is written before they all parse.
    auto t0 = Clock::now();
    Scene scene = config.demo ? make_demo_scene() : load_scene_meshes(config.meshes);
    int width = 0, height = 0;
    const RayBatch rays = cast_scan_rays(config, width, height);
    result.load_s = seconds_since(t0);
    result.triangles = scene.triangle_count();
    result.parts = scene.parts;
    result.rays = rays.size();

    t0 = Clock::now();
    const auto backend = make_backend(config.backend, scene.geometry, pool, config.backend_config);
    result.build_s = seconds_since(t0);

    t0 = Clock::now();
    HitBatch hits;
    hits.resize(rays.size());
    if (progress) {
        progress(0, rays.size());  // the trace starts: rates count from here
    }
    for (std::size_t b = 0; b < rays.size(); b += kTraceChunk) {
        throw_if_cancelled(config.cancel, "scan");
        const std::size_t e = std::min(rays.size(), b + kTraceChunk);
        backend->intersect(rays, b, e, hits, pool);
        if (progress) {
            progress(e, rays.size());
        }
    }
    result.trace_s = seconds_since(t0);

    t0 = Clock::now();
    ScanWritten written = write_scan_outputs(config, rays, hits, width, height, pool);
    result.write_s = seconds_since(t0);
    result.hits = written.hits;
    result.points_written = written.points_written;
    result.outputs = std::move(written.outputs);
    result.notes = std::move(written.notes);
    result.few_hits_reasons = detail::diagnose_scan(rays, result.hits, scene.geometry.bounds());
    return result;
}

}  // namespace beamtrace
