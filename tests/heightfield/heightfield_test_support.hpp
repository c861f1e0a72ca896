// Helpers for the height-field tests: small synthetic grids and image comparison.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "beamtrace/heightfield/section_grid.hpp"
#include "beamtrace/heightfield/view_renderer.hpp"
#include "beamtrace/heightfield/view_session.hpp"
#include "beamtrace/io/las_writer.hpp"

namespace beamtrace::test {

/// Writes `points` to a LAS file at centimetre resolution around the origin; returns `path`.
inline std::filesystem::path write_test_las(const std::filesystem::path& path,
                                            const std::vector<LasPoint>& points, int point_format) {
    LasWriterConfig config;
    config.point_format = point_format;
    config.scale = {0.01, 0.01, 0.01};
    LasWriter writer(path, config);
    writer.write(points);
    writer.close();
    return path;
}

/// Writes a LAS file of ground at z = 0 in every 1 m cell of [0.5, 32.5)^2 and a 10 m high bridge
/// deck over x in [14.5, 18.5) (a second point in those cells), and returns its path.
inline std::filesystem::path write_bridge_las(const std::filesystem::path& path) {
    std::vector<LasPoint> points;
    for (int y = 0; y < 32; ++y) {
        for (int x = 0; x < 32; ++x) {
            LasPoint p;
            p.x = x + 0.5;
            p.y = y + 0.5;
            p.z = 0.0;
            p.return_number = p.number_of_returns = 1;
            points.push_back(p);
            if (x >= 14 && x < 18) {
                p.z = 10.0;
                points.push_back(p);
            }
        }
    }
    return write_test_las(path, points, 6);
}

/// The view of write_bridge_las's file the stack tests use: 1 m cells, 2 x 2 sections of 8
/// cells, `stacks` height stacks 1 m apart at most.
inline ViewSessionConfig bridge_view_config(int stacks) {
    ViewSessionConfig c;
    c.field.cell_size = 1.0;
    c.field.levels = 3;
    c.field.section_cells = 8;
    c.field.sections = 2;
    c.field.height_stacks = stacks;
    c.field.stack_gap = 1.0;
    c.threads = 2;
    return c;
}

/// A grid whose sections are all resident and filled by `height(x, y)` over window cells (NaN
/// for an empty cell), attribute = x + y * 65536.
inline void fill_grid(SectionGrid& grid,
                      const std::function<double(std::int64_t, std::int64_t)>& height) {
    const std::int64_t w = grid.window_cells();
    const Vec3d corner = grid.window_corner();
    const double cell = grid.config().cell_size;
    const std::vector<Bounds2> all = {{corner.x, corner.y, corner.x + static_cast<double>(w) * cell,
                                       corner.y + static_cast<double>(w) * cell}};
    const double mid = corner.x + static_cast<double>(w) * cell / 2;
    const std::vector<int> slots =
        grid.recenter(mid, corner.y + static_cast<double>(w) * cell / 2, all, 0);
    const int shift = grid.layout().finest_shift();
    const int n = grid.sections_per_side();
    for (std::int64_t y = 0; y < w; ++y) {
        for (std::int64_t x = 0; x < w; ++x) {
            const double h = height(x, y);
            if (std::isnan(h)) {
                continue;
            }
            HeightSection* s = grid.slot(static_cast<int>((y >> shift) * n + (x >> shift)));
            const std::int64_t mask = (std::int64_t{1} << shift) - 1;
            s->insert(static_cast<int>(x & mask), static_cast<int>(y & mask), static_cast<float>(h),
                      static_cast<std::uint32_t>(x + y * 65536));
        }
    }
    for (const int s : slots) {
        grid.slot(s)->build_mipmap();
        grid.mark_loaded(s);
    }
}

/// Pixels whose colour differs or whose depth differs by more than 1e-6 relative.
inline std::size_t count_mismatches(const ViewImage& a, const ViewImage& b, std::string& first) {
    std::size_t bad = 0;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        const float da = a.depth[i], db = b.depth[i];
        const bool depth_ok = (std::isinf(da) && std::isinf(db)) ||
                              std::abs(da - db) <= 1e-6f * std::max(1.0f, std::abs(da));
        const bool rgb_ok = a.rgb[3 * i] == b.rgb[3 * i] && a.rgb[3 * i + 1] == b.rgb[3 * i + 1] &&
                            a.rgb[3 * i + 2] == b.rgb[3 * i + 2];
        if (!depth_ok || !rgb_ok) {
            if (bad == 0) {
                first = "pixel " + std::to_string(i % static_cast<std::size_t>(a.width)) + "," +
                        std::to_string(i / static_cast<std::size_t>(a.width)) + " depth " +
                        std::to_string(da) + " vs " + std::to_string(db);
            }
            ++bad;
        }
    }
    return bad;
}

}  // namespace beamtrace::test
