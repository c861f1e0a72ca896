// libFuzzer target: the STL, ascii and binary (load_stl) mesh loader, on a file holding the input.
#include <cstddef>
#include <cstdint>

#include "beamtrace/scene/mesh_loader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.stl");
    return beamtrace::fuzz::run_guarded([&] { (void)beamtrace::load_stl(path); });
}
