// libFuzzer target: the LAS reader (header, VLRs, EVLRs, every point record format), on a file
// holding the input. Reads all points in small chunks, then seeks back to the middle and reads on;
// reads the CRS records (GeoTIFF keys, WKT) as `beamtrace info` does.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "beamtrace/io/las_crs.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.las");
    return beamtrace::fuzz::run_guarded([&] {
        beamtrace::LasReader reader(path);
        (void)beamtrace::las_file_crs(reader.header(), reader.vlrs());
        std::array<beamtrace::LasPoint, 64> chunk;
        while (reader.read(chunk) != 0) {
        }
        const std::uint64_t count = reader.header().point_count;
        reader.seek(count / 2);
        (void)reader.read(std::span(chunk).first(3));
    });
}
