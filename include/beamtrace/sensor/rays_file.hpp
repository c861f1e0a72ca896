// Ray lists as CSV text: one ray per line, `ox,oy,oz,dx,dy,dz`.
#pragma once

#include <filesystem>

#include "beamtrace/core/ray_batch.hpp"

namespace beamtrace {

/// Reads rays from a CSV file: one ray per line `ox,oy,oz,dx,dy,dz` (commas with optional spaces
/// or tabs around them; CRLF line ends accepted). Blank lines and lines starting with `#` are
/// skipped, and so is a first line made only of non-numeric words (a header such as
/// `ox,oy,oz,dx,dy,dz`). Directions are scaled to unit length, so hit distances are metres; a
/// direction already unit to within 16 ulps is kept bit for bit, so write/read round trips are
/// exact. Every ray gets tmin = 0, tmax = +inf.
///
/// Throws InputError naming the file and line for a wrong field count, a malformed or non-finite
/// number or a zero-length direction, and naming the file when it cannot be read or holds no rays.
[[nodiscard]] RayBatch read_rays_csv(const std::filesystem::path& path);

/// Writes the header `ox,oy,oz,dx,dy,dz` and one line per ray, each number in the shortest form
/// that reads back as the same double. tmin/tmax are not part of the format. Written atomically;
/// throws OutputError naming the path (and the ray) for a non-finite value or a malformed batch.
void write_rays_csv(const std::filesystem::path& path, const RayBatch& rays);

}  // namespace beamtrace
