// libFuzzer target: the ESRI ASCII grid raster loader (load_esri_ascii_grid), on a file holding the
// input, and the triangulation of the raster it returns.
#include <cstddef>
#include <cstdint>

#include "beamtrace/scene/raster_terrain.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.asc");
    return beamtrace::fuzz::run_guarded([&] {
        const beamtrace::Raster raster = beamtrace::load_esri_ascii_grid(path);
        (void)beamtrace::raster_to_mesh(raster);
    });
}
