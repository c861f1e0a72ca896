// Chooses a mesh loader by file extension.
#include "beamtrace/scene/mesh_loader.hpp"

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/gltf_loader.hpp"

namespace beamtrace {

TriangleMesh load_mesh(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) {
        if (c >= 'A' && c <= 'Z') {
            c = static_cast<char>(c - 'A' + 'a');
        }
    }
    if (ext == ".obj") {
        return load_obj(path);
    }
    if (ext == ".ply") {
        return load_ply(path);
    }
    if (ext == ".stl") {
        return load_stl(path);
    }
    if (ext == ".gltf" || ext == ".glb") {
        return load_gltf(path);
    }
    throw InputError(path.string(), "unknown mesh format '" + path.extension().string() +
                                        "' (expected .obj, .ply, .stl, .gltf or .glb)");
}

}  // namespace beamtrace
