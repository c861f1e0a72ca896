#include "beamtrace/heightfield/las_ingest.hpp"

#include "beamtrace/heightfield/gap_fill.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/las_reader.hpp"

namespace beamtrace {
namespace {

template <typename T>
[[nodiscard]] T load(const std::uint8_t* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
}

/// Closes a file descriptor when it goes out of scope.
struct FileDescriptor {
    int fd = -1;
    ~FileDescriptor() {
        if (fd >= 0) {
            ::close(fd);
        }
    }
};

void read_block(int fd, const std::filesystem::path& path, std::uint8_t* data, std::size_t size,
                std::uint64_t offset) {
    std::size_t done = 0;
    while (done < size) {
        const ::ssize_t n =
            ::pread(fd, data + done, size - done, static_cast<::off_t>(offset + done));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            throw InputError(path.string(), "point data: read failed at byte " +
                                                std::to_string(offset + done) +
                                                (n < 0 ? std::string(": ") + std::strerror(errno)
                                                       : std::string(": the file ends early")));
        }
        done += static_cast<std::size_t>(n);
    }
}

/// Where the fields the loader needs sit in a record of one file.
struct RecordLayout {
    std::size_t length = 0;
    std::size_t classification = 15;
    bool legacy_class = true;  ///< formats 0-5 keep flags in the class byte
    std::size_t rgb = 0;       ///< 0: no colour
};

/// The global cell of raw coordinate `raw`: floor(raw * a + b). The grid's origin is the lowest
/// header bound, and a point on it can round to cell -1: within its header's bounds (raw at or
/// above `lo_raw`) it is cell 0.
[[nodiscard]] std::int64_t global_cell(double raw, double a, double b, double lo_raw) {
    const auto c = static_cast<std::int64_t>(std::floor(raw * a + b));
    return c < 0 && raw >= lo_raw ? 0 : c;
}

[[nodiscard]] RecordLayout record_layout(const LasHeader& h) {
    RecordLayout r;
    r.length = h.point_record_length;
    if (las_format_is_extended(h.point_format)) {
        r.classification = 16;
        r.legacy_class = false;
    }
    if (las_format_has_rgb(h.point_format)) {
        r.rgb = las_format_is_extended(h.point_format)
                    ? 30
                    : (las_format_has_gps_time(h.point_format) ? 28 : 20);
    }
    return r;
}

}  // namespace

IngestStats ingest_into(const LasSourceSet& sources, const HeightFieldConfig& field,
                        const Vec3d& origin, std::span<const IngestTarget> targets_in,
                        ThreadPool& pool, const IngestConfig& config,
                        const IngestProgress& progress, const std::atomic<bool>* cancel) {
    const auto start = std::chrono::steady_clock::now();
    IngestStats stats;
    if (targets_in.empty()) {
        return stats;
    }
    // The targets' bounding box of sections, as a table; points are binned by global cell.
    std::int64_t sx0 = targets_in[0].section_x, sy0 = targets_in[0].section_y;
    std::int64_t sx1 = sx0, sy1 = sy0;
    for (const IngestTarget& t : targets_in) {
        sx0 = std::min(sx0, t.section_x);
        sy0 = std::min(sy0, t.section_y);
        sx1 = std::max(sx1, t.section_x);
        sy1 = std::max(sy1, t.section_y);
    }
    const std::int64_t n = sx1 - sx0 + 1;
    const std::int64_t rows = sy1 - sy0 + 1;
    std::vector<HeightSection*> targets(static_cast<std::size_t>(n * rows), nullptr);
    for (const IngestTarget& t : targets_in) {
        targets[static_cast<std::size_t>((t.section_y - sy0) * n + (t.section_x - sx0))] =
            t.section;
    }
    const int shift = field.layout().finest_shift();
    const std::int64_t first_x = sx0 << shift, first_y = sy0 << shift;
    const std::int64_t window_x = n << shift, window_y = rows << shift;
    const std::int64_t mask = (std::int64_t{1} << shift) - 1;
    const double cell = field.cell_size;
    const ColorMode mode = field.color;
    const auto tasks = static_cast<std::size_t>(std::max(1u, pool.size()));

    std::vector<std::uint64_t> inserted(tasks, 0);
    std::uint64_t outside = 0;
    std::uint32_t max_intensity = 0;
    std::uint64_t done_points = 0;
    std::vector<std::uint8_t> buffer;

    for (const LasSource& source : sources.files()) {
        const LasHeader& h = source.header;
        if (h.point_count == 0) {
            continue;
        }
        const RecordLayout rec = record_layout(h);
        const std::size_t per_block = std::max<std::size_t>(1, config.block_bytes / rec.length);
        buffer.resize(per_block * rec.length);
        // LAZ files are decoded by the LAS reader; LAS records are read as they are.
        std::unique_ptr<LasReader> laz;
        FileDescriptor file;
        if (source.compressed) {
            laz = std::make_unique<LasReader>(source.path, pool.size());
        } else {
            file.fd = ::open(source.path.c_str(), O_RDONLY | O_CLOEXEC);
            if (file.fd < 0) {
                throw InputError(source.path.string(),
                                 std::string("cannot open: ") + std::strerror(errno));
            }
            ::posix_fadvise(file.fd, 0, 0, POSIX_FADV_SEQUENTIAL);
        }
        // Global cell = floor(raw * a + b) (per axis); height = raw * scale + offset - origin.
        const double ax = h.scale.x / cell, bx = (h.offset.x - origin.x) / cell;
        const double ay = h.scale.y / cell, by = (h.offset.y - origin.y) / cell;
        const double az = h.scale.z, bz = h.offset.z - origin.z;
        // Raw integer bounds of the header box, widened by half a step.
        const auto raw_bound = [&](double v, double scale, double offset) {
            return (v - offset) / scale;
        };
        const double lo_x = raw_bound(h.min.x, h.scale.x, h.offset.x) - 0.5;
        const double hi_x = raw_bound(h.max.x, h.scale.x, h.offset.x) + 0.5;
        const double lo_y = raw_bound(h.min.y, h.scale.y, h.offset.y) - 0.5;
        const double hi_y = raw_bound(h.max.y, h.scale.y, h.offset.y) + 0.5;
        const double lo_z = raw_bound(h.min.z, h.scale.z, h.offset.z) - 0.5;
        const double hi_z = raw_bound(h.max.z, h.scale.z, h.offset.z) + 0.5;
        bool rgb16 = true;
        bool first_block = true;
        std::uint64_t file_outside = 0;

        for (std::uint64_t first = 0; first < h.point_count; first += per_block) {
            if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
                stats.cancelled = true;
                break;
            }
            const auto count =
                static_cast<std::size_t>(std::min<std::uint64_t>(per_block, h.point_count - first));
            if (laz) {
                if (laz->read_records(std::span(buffer).first(count * rec.length)) != count) {
                    throw InputError(source.path.string(),
                                     "point data: fewer points than the "
                                     "header says");
                }
            } else {
                read_block(file.fd, source.path, buffer.data(), count * rec.length,
                           h.offset_to_point_data + first * rec.length);
            }
            const std::uint8_t* records = buffer.data();
            if (first_block && rec.rgb != 0) {
                // 8-bit colours stored in the 16-bit fields: decided on the first block.
                std::uint16_t top = 0;
                for (std::size_t i = 0; i < count; ++i) {
                    const std::uint8_t* c = records + i * rec.length + rec.rgb;
                    top = std::max({top, load<std::uint16_t>(c), load<std::uint16_t>(c + 2),
                                    load<std::uint16_t>(c + 4)});
                }
                rgb16 = top > 255;
            }
            first_block = false;
            const int rgb_shift = rgb16 ? 8 : 0;
            std::uint32_t block_max_intensity = 0;
            std::uint64_t block_outside = 0;
            pool.parallel_for(tasks, 1, [&](std::size_t begin, std::size_t end) {
                for (std::size_t task = begin; task < end; ++task) {
                    std::uint64_t mine = 0;
                    for (std::size_t i = 0; i < count; ++i) {
                        const std::uint8_t* r = records + i * rec.length;
                        const auto rx = static_cast<double>(load<std::int32_t>(r));
                        const auto ry = static_cast<double>(load<std::int32_t>(r + 4));
                        const std::int64_t gy = global_cell(ry, ay, by, lo_y) - first_y;
                        if (task == 0) {
                            const std::uint16_t intensity = load<std::uint16_t>(r + 12);
                            block_max_intensity =
                                std::max<std::uint32_t>(block_max_intensity, intensity);
                            const auto rz = static_cast<double>(load<std::int32_t>(r + 8));
                            if (rx < lo_x || rx > hi_x || ry < lo_y || ry > hi_y || rz < lo_z ||
                                rz > hi_z) {
                                ++block_outside;
                            }
                        }
                        if (gy < 0 || gy >= window_y ||
                            static_cast<std::size_t>(gy >> 3) % tasks != task) {
                            continue;
                        }
                        const std::int64_t gx = global_cell(rx, ax, bx, lo_x) - first_x;
                        if (gx < 0 || gx >= window_x) {
                            continue;
                        }
                        HeightSection* s =
                            targets[static_cast<std::size_t>((gy >> shift) * n + (gx >> shift))];
                        if (s == nullptr) {
                            continue;
                        }
                        const auto z = static_cast<float>(
                            static_cast<double>(load<std::int32_t>(r + 8)) * az + bz);
                        std::uint32_t attribute = 0;
                        switch (mode) {
                            case ColorMode::height:
                                break;
                            case ColorMode::rgb:
                                if (rec.rgb != 0) {
                                    const std::uint8_t* c = r + rec.rgb;
                                    attribute = pack_rgb8(
                                        (load<std::uint16_t>(c) >> rgb_shift) & 0xFFu,
                                        (load<std::uint16_t>(c + 2) >> rgb_shift) & 0xFFu,
                                        (load<std::uint16_t>(c + 4) >> rgb_shift) & 0xFFu);
                                } else {
                                    attribute = pack_rgb8(255, 255, 255);
                                }
                                break;
                            case ColorMode::intensity:
                                attribute = load<std::uint16_t>(r + 12);
                                break;
                            case ColorMode::classification:
                                attribute = rec.legacy_class ? (r[rec.classification] & 0x1Fu)
                                                             : r[rec.classification];
                                break;
                        }
                        s->insert(static_cast<int>(gx & mask), static_cast<int>(gy & mask), z,
                                  attribute);
                        ++mine;
                    }
                    inserted[task] += mine;
                }
            });
            max_intensity = std::max(max_intensity, block_max_intensity);
            file_outside += block_outside;
            done_points += count;
            if (progress) {
                progress(done_points, sources.point_count());
            }
        }
        if (file_outside > 0) {
            stats.warnings.push_back(source.path.string() + ": " + std::to_string(file_outside) +
                                     " points lie outside the header bounds");
        }
        outside += file_outside;
    }
    buffer = {};

    if (!stats.cancelled) {
        pool.parallel_for(targets_in.size(), 1, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                fill_gaps(*targets_in[i].section, field.gap_fill_cells);
                targets_in[i].section->build_mipmap();
            }
        });
        stats.sections_loaded = static_cast<int>(targets_in.size());
    }
    stats.max_intensity = max_intensity;
    stats.points_read = done_points;
    for (const auto v : inserted) {
        stats.points_inserted += v;
    }
    stats.points_outside_header = outside;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

IngestStats ingest_sections(const LasSourceSet& sources, SectionGrid& grid,
                            std::span<const int> slots, ThreadPool& pool,
                            const IngestConfig& config, const IngestProgress& progress) {
    std::vector<IngestTarget> targets;
    for (const int s : slots) {
        targets.push_back({grid.section_x(s), grid.section_y(s), grid.slot(s)});
    }
    IngestStats stats =
        ingest_into(sources, grid.config(), grid.origin(), targets, pool, config, progress);
    for (const int s : slots) {
        grid.mark_loaded(s);
    }
    if (stats.max_intensity > 0) {
        grid.set_intensity_full_scale(
            std::max(static_cast<double>(stats.max_intensity), grid.intensity_full_scale()));
    }
    return stats;
}

}  // namespace beamtrace
