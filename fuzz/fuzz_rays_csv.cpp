// libFuzzer target: rays CSV files (read_rays_csv), on a file holding the input.
#include <cstddef>
#include <cstdint>

#include "beamtrace/sensor/rays_file.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.csv");
    return beamtrace::fuzz::run_guarded([&] { (void)beamtrace::read_rays_csv(path); });
}
