// libFuzzer target: the glTF 2.0, .gltf and .glb (load_gltf) mesh loader, on a file holding the
// input.
#include <cstddef>
#include <cstdint>

#include "beamtrace/scene/gltf_loader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.gltf");
    return beamtrace::fuzz::run_guarded([&] { (void)beamtrace::load_gltf(path); });
}
