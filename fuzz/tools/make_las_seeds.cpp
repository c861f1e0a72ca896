// Writes the LAS seeds of fuzz/corpus/las_reader/ with beamtrace's own LasWriter: a few points in
// each point format the writer has (6, 7, 8), one file with a VLR, an EVLR and extra bytes, and
// one with no points. Run by hand when the seeds need remaking (docs/dev/fuzzing.md):
//     build/fuzz/beamtrace_fuzz_make_las_seeds fuzz/corpus/las_reader
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "beamtrace/io/las_writer.hpp"

namespace {

std::vector<beamtrace::LasPoint> points(std::size_t count, std::uint16_t extra_bytes) {
    std::vector<beamtrace::LasPoint> out(count);
    for (std::size_t i = 0; i < count; ++i) {
        auto& p = out[i];
        p.x = 1.5 * static_cast<double>(i);
        p.y = -2.25 * static_cast<double>(i);
        p.z = 10.0 + 0.125 * static_cast<double>(i);
        p.gps_time = 1000.0 + static_cast<double>(i);
        p.intensity = static_cast<std::uint16_t>(100 * i);
        p.return_number = 1;
        p.number_of_returns = static_cast<std::uint8_t>(1 + i % 2);
        p.classification = static_cast<std::uint8_t>(i % 3);
        p.red = 1000;
        p.nir = 7;
        p.extra_bytes.assign(extra_bytes, static_cast<std::uint8_t>(i));
    }
    return out;
}

void write(const std::filesystem::path& path, beamtrace::LasWriterConfig config,
           std::size_t count) {
    beamtrace::LasWriter writer(path, config);
    writer.write(points(count, config.extra_bytes_per_point));
    writer.close();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: beamtrace_fuzz_make_las_seeds FOLDER\n";
        return 2;
    }
    const std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir);
    for (const int format : {6, 7, 8}) {
        beamtrace::LasWriterConfig config;
        config.point_format = format;
        config.creation_day_of_year = 1;
        config.creation_year = 2026;
        write(dir / ("format" + std::to_string(format) + ".las"), config, 3);
    }
    beamtrace::LasWriterConfig config;
    config.creation_day_of_year = 1;
    config.creation_year = 2026;
    write(dir / "empty.las", config, 0);
    config.extra_bytes_per_point = 2;
    config.vlrs.push_back({"beamtrace", 1, "seed vlr", {1, 2, 3, 4}, false, 0});
    config.vlrs.push_back({"beamtrace", 2, "seed evlr", {5, 6, 7}, true, 0});
    write(dir / "vlrs_extra_bytes.las", config, 2);
    return 0;
}
