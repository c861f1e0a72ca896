// libFuzzer target: the Wavefront OBJ (load_obj) mesh loader, on a file holding the input.
#include <cstddef>
#include <cstdint>

#include "beamtrace/scene/mesh_loader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.obj");
    return beamtrace::fuzz::run_guarded([&] { (void)beamtrace::load_obj(path); });
}
