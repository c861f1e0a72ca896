// Per-ray hit tables as CSV: `ray,range_m,face_id`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/hit_batch.hpp"

namespace beamtrace {

/// Writes the header `ray,range_m,face_id` and one row per ray in order: `i,<range>,<face>`,
/// the range in the shortest form that reads back as the same float; a miss is `i,inf,-1`.
/// Written atomically; throws OutputError naming the path.
void write_hits_csv(const std::filesystem::path& path, const HitBatch& hits);

/// The first line of write_hits_csv's file, newline included.
inline constexpr std::string_view kHitsCsvHeader = "ray,range_m,face_id\n";

/// Appends the rows of rays [begin, end) exactly as write_hits_csv writes them: for writers that
/// format parts of the table on several threads.
void append_hits_csv_rows(const HitBatch& hits, std::size_t begin, std::size_t end,
                          std::string& out);

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
