// libFuzzer target: the GeoTIFF raster loader (load_geotiff), on a file holding the input, and the
// triangulation of the raster it returns.
#include <cstddef>
#include <cstdint>

#include "beamtrace/scene/raster_terrain.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.tif");
    return beamtrace::fuzz::run_guarded([&] {
        const beamtrace::Raster raster = beamtrace::load_geotiff(path);
        (void)beamtrace::raster_to_mesh(raster);
    });
}
