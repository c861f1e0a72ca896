// glTF 2.0 scenes (.gltf with external or data-URI buffers, and binary .glb) as one triangle set.
//
// The default scene (`scene`, else `scenes[0]`, else every root node) is walked depth first,
// each node's transform (`matrix`, or `translation` * `rotation` * `scale`) composed down the tree
// and applied to the vertex positions. Every primitive of mode TRIANGLES (4, the default),
// TRIANGLE_STRIP (5) or TRIANGLE_FAN (6) becomes triangles, following the winding rules of the
// glTF specification (3.7.2.1); POINTS and LINE* primitives are skipped. Face IDs follow the
// walk: nodes in depth-first pre-order, each node's mesh primitives in order, each primitive's
// triangles in order. A mesh used by two nodes is emitted twice. Each primitive gets its own
// vertices (all of its POSITION accessor, transformed); coordinates stay in the file's frame
// (glTF is +Y up), in the file's units (metres by the specification).
#pragma once

#include <filesystem>

#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

/// Loads a .gltf or .glb file (told apart by the GLB magic, not the extension). POSITION may be
/// float or (KHR_mesh_quantization) an 8/16-bit integer type, normalized or not; indices u8/u16/
/// u32; sparse accessors are applied. Throws InputError naming the file and the JSON path of the
/// problem, e.g. `model.gltf: accessors[3]: index 30 out of range (24 vertices)`, for malformed
/// JSON or GLB containers, missing or short buffers, accessors running past their buffer view,
/// indices out of range, unsupported required extensions, and files with no triangles at all.
[[nodiscard]] TriangleMesh load_gltf(const std::filesystem::path& path);

}  // namespace beamtrace
