// LAZ decode rate (points/s) of LasReader on real files of ../shared/data/las/laz, point
// formats 1 (point-wise, LASzip 2) and 6/8 (layered, LASzip 3), at 1 and 2 decoding threads:
// opening the file (header, VLRs, chunk table) and decoding every record, as `info --stats` and
// `view` do. bench/laz_decode.sh sets these beside laz-perf's rate on the same files.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "beamtrace/io/las_reader.hpp"

namespace bt = beamtrace;

namespace {

constexpr std::array<const char*, 4> kFiles = {
    "Megaplot.laz",                          // format 1, 81 590 points, 2 chunks
    "Topography.laz",                        // format 1, 73 403 points
    "lone-star.copc.laz",                    // format 6 (COPC), 518 862 points
    "las_with_several_extra_byte_bloc.laz",  // format 8 + 3 extra bytes, 697 721 points
};

std::filesystem::path laz_file(std::size_t index) {
    return std::filesystem::path(BEAMTRACE_SHARED_DATA_DIR) / "las/laz" / kFiles.at(index);
}

void BM_LazDecode(benchmark::State& state) {
    const auto path = laz_file(static_cast<std::size_t>(state.range(0)));
    const auto threads = static_cast<unsigned>(state.range(1));
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        state.SkipWithError(("missing " + path.string()).c_str());
        return;
    }
    state.SetLabel(path.filename().string());
    std::vector<std::uint8_t> buffer;
    std::uint64_t points = 0;
    for (auto _ : state) {
        bt::LasReader reader(path, threads);
        buffer.resize(std::size_t{1 << 16} * reader.header().point_record_length);
        points = reader.header().point_count;
        while (reader.read_records(buffer) != 0) {
        }
        benchmark::DoNotOptimize(buffer.data());
    }
    state.counters["points/s"] = benchmark::Counter(static_cast<double>(points),
                                                    benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_LazDecode)
    ->ArgsProduct({{0, 1, 2, 3}, {1, 2}})
    ->ArgNames({"file", "threads"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5);
