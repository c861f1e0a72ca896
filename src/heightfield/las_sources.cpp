#include "beamtrace/heightfield/las_sources.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"

namespace beamtrace {
namespace {

[[nodiscard]] bool has_las_extension(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".las" || ext == ".laz";
}

}  // namespace

LasSourceSet::LasSourceSet(std::span<const std::filesystem::path> inputs) {
    if (inputs.empty()) {
        throw ConfigError("no input LAS files");
    }
    for (const auto& input : inputs) {
        std::error_code ec;
        if (std::filesystem::is_directory(input, ec)) {
            std::vector<std::filesystem::path> found;
            for (const auto& entry : std::filesystem::directory_iterator(input, ec)) {
                if (entry.is_regular_file() && has_las_extension(entry.path())) {
                    found.push_back(entry.path());
                }
            }
            if (ec) {
                throw InputError(input.string(), "cannot list directory: " + ec.message());
            }
            if (found.empty()) {
                throw InputError(input.string(), "directory holds no .las files");
            }
            std::sort(found.begin(), found.end());
            for (const auto& f : found) {
                add_file(f);
            }
        } else {
            add_file(input);
        }
    }
}

void LasSourceSet::add_file(const std::filesystem::path& path) {
    LasSource source{path, {}};
    {
        const LasReader reader(path);  // validates the header, VLRs and file length
        source.header = reader.header();
        source.compressed = reader.compressed();
    }
    const LasHeader& h = source.header;
    if (h.point_count == 0) {
        warnings_.push_back(path.string() + ": no points");
        files_.push_back(std::move(source));
        return;
    }
    for (std::size_t k = 0; k < 3; ++k) {
        if (!std::isfinite(h.min[k]) || !std::isfinite(h.max[k]) || h.min[k] > h.max[k]) {
            throw InputError(path.string(), std::string("header: ") + "xyz"[k] + " bounds [" +
                                                std::to_string(h.min[k]) + ", " +
                                                std::to_string(h.max[k]) +
                                                "] are not usable (min > max or not finite)");
        }
    }
    if (bounds_.empty()) {
        min_ = h.min;
        max_ = h.max;
    } else {
        min_ = beamtrace::min(min_, h.min);
        max_ = beamtrace::max(max_, h.max);
    }
    bounds_.push_back({h.min.x, h.min.y, h.max.x, h.max.y});
    point_count_ += h.point_count;
    files_.push_back(std::move(source));
}

int auto_levels(const LasSourceSet& sources, const HeightFieldConfig& field) {
    const double extent =
        std::max(sources.max().x - sources.min().x, sources.max().y - sources.min().y);
    // One section twice the data's extent: the data lies in one or two sections of any window
    // whose camera is within a few extents of it (the window follows the camera).
    const double want = 2.0 * extent;
    int levels = 1;
    while (levels < field.levels && static_cast<double>(field.section_cells) *
                                            std::ldexp(1.0, levels - 1) * field.cell_size <
                                        want) {
        ++levels;
    }
    return levels;
}

double auto_cell_size(const LasSourceSet& sources) {
    double area = 0.0;
    for (const Bounds2& b : sources.bounds()) {
        area += std::max(0.0, b.max_x - b.min_x) * std::max(0.0, b.max_y - b.min_y);
    }
    if (sources.point_count() == 0 || !(area > 0) || !std::isfinite(area)) {
        return 1.0;
    }
    const double want =
        kAutoCellSpacings * std::sqrt(area / static_cast<double>(sources.point_count()));
    double step = std::pow(10.0, std::floor(std::log10(want)));
    for (const double m : {1.0, 2.0, 5.0, 10.0}) {
        if (m * step >= want * (1.0 - 1e-12)) {
            return m * step;
        }
    }
    return 10.0 * step;
}

}  // namespace beamtrace
