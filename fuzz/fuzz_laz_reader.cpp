// libFuzzer target: the LAZ path of the LAS reader (LASzip VLR, chunk table, point-wise and
// layered chunk decoders), on a file holding the input. Reads all points in small chunks with
// one decoding thread, then seeks back to the middle and reads on.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "beamtrace/io/las_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.laz");
    return beamtrace::fuzz::run_guarded([&] {
        beamtrace::LasReader reader(path, 1);
        std::array<beamtrace::LasPoint, 64> chunk;
        while (reader.read(chunk) != 0) {
        }
        const std::uint64_t count = reader.header().point_count;
        reader.seek(count / 2);
        (void)reader.read(std::span(chunk).first(3));
    });
}
