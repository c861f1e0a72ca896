// Per-ray hit tables as CSV: `ray,range_m,face_id`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "beamtrace/core/hit_batch.hpp"

namespace beamtrace {

/// Writes the header `ray,range_m,face_id` and one row per ray in order: `i,<range>,<face>`,
/// the range in the shortest form that reads back as the same float; a miss is `i,inf,-1`.
/// Written atomically; throws OutputError naming the path.
void write_hits_csv(const std::filesystem::path& path, const HitBatch& hits);

/// The columns of a hits CSV file. A miss has range_m = +inf and face_id = -1.
struct HitsCsv {
    std::vector<std::uint64_t> ray;
    std::vector<double> range_m;
    std::vector<std::int64_t> face_id;

    [[nodiscard]] std::size_t size() const { return ray.size(); }
};

/// Reads a file written by write_hits_csv. Throws InputError with file and line on a missing
/// header, a wrong field count or a malformed number.
[[nodiscard]] HitsCsv read_hits_csv(const std::filesystem::path& path);

}  // namespace beamtrace
