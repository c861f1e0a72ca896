// libFuzzer target: trajectory CSV files (read_trajectory_csv), on a file holding the input,
// and the pose at both ends and the middle of the trajectory read.
#include <cstddef>
#include <cstdint>

#include "beamtrace/sensor/trajectory.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = beamtrace::fuzz::write_input(data, size, "input.csv");
    return beamtrace::fuzz::run_guarded([&] {
        const beamtrace::SampledTrajectory trajectory = beamtrace::read_trajectory_csv(path);
        const double start = trajectory.start_time_s();
        const double end = trajectory.end_time_s();
        (void)trajectory.pose_at(start);
        (void)trajectory.pose_at(start + 0.5 * (end - start));
        (void)trajectory.pose_at(end);
    });
}
