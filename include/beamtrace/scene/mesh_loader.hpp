// Triangle-mesh loaders for OBJ, PLY and STL files, and the dispatcher that also reads glTF
// (see gltf_loader.hpp).
//
// Every loader returns an indexed triangle set whose face IDs follow the file order: a polygon
// with n > 3 vertices becomes the fan (v0, vi, vi+1), i = 1..n-2, and each triangle takes the next
// ID. Degenerate triangles are kept so that IDs stay aligned with the file. Vertices are stored as
// float. Any problem with the file (unreadable, malformed, truncated, an index out of range, no
// triangles at all) throws InputError naming the file, and the line for text formats.
#pragma once

#include <filesystem>

#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

/// Wavefront OBJ: `v` and `f` lines (all index forms, negative indices); everything else ignored.
[[nodiscard]] TriangleMesh load_obj(const std::filesystem::path& path);

/// PLY (ascii, binary_little_endian, binary_big_endian): `vertex` x/y/z of any scalar type and
/// `face` `vertex_indices` (or `vertex_index`) lists; other properties and elements are skipped.
[[nodiscard]] TriangleMesh load_ply(const std::filesystem::path& path);

/// STL, binary or ASCII (several `solid` blocks allowed). One face per facet, in file order;
/// every facet gets three new vertices (vertices are not welded).
[[nodiscard]] TriangleMesh load_stl(const std::filesystem::path& path);

/// Chooses by extension (.obj, .ply, .stl, .gltf, .glb; case-insensitive); throws InputError for
/// others.
[[nodiscard]] TriangleMesh load_mesh(const std::filesystem::path& path);

}  // namespace beamtrace
