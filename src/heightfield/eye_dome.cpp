#include "beamtrace/heightfield/eye_dome.hpp"

#include <array>
#include <cmath>
#include <utility>

#include "beamtrace/core/thread_pool.hpp"

namespace beamtrace {

double eye_dome_shade(const ViewImage& image, int x, int y, double strength) {
    const auto at = [&](int u, int v) {
        return static_cast<std::size_t>(v) * static_cast<std::size_t>(image.width) +
               static_cast<std::size_t>(u);
    };
    const float d = image.depth[at(x, y)];
    if (!std::isfinite(d) || !(d > 0.0f)) {
        return 1.0;
    }
    const double log_d = std::log2(static_cast<double>(d));
    constexpr int r = kEyeDomeRadius;
    static constexpr std::array<std::pair<int, int>, 8> kAround = {
        {{-r, 0}, {r, 0}, {0, -r}, {0, r}, {-r, -r}, {r, -r}, {-r, r}, {r, r}}};
    double response = 0.0;
    for (const auto& [dx, dy] : kAround) {
        const int u = x + dx, v = y + dy;
        if (u < 0 || v < 0 || u >= image.width || v >= image.height) {
            continue;
        }
        const float n = image.depth[at(u, v)];
        if (std::isfinite(n) && n > 0.0f) {
            response += std::max(0.0, log_d - std::log2(static_cast<double>(n)));
        }
    }
    return std::exp(-100.0 * strength * response / static_cast<double>(kAround.size()));
}

void apply_eye_dome(ViewImage& image, double strength, ThreadPool& pool) {
    if (!(strength > 0.0) || image.width <= 0 || image.height <= 0) {
        return;
    }
    // Shades from the untouched depths into a separate buffer, then applied: any row split.
    std::vector<float> shade(image.depth.size(), 1.0f);
    pool.parallel_for(
        static_cast<std::size_t>(image.height), 16, [&](std::size_t begin, std::size_t end) {
            for (std::size_t y = begin; y < end; ++y) {
                for (int x = 0; x < image.width; ++x) {
                    shade[y * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)] =
                        static_cast<float>(eye_dome_shade(image, x, static_cast<int>(y), strength));
                }
            }
        });
    for (std::size_t i = 0; i < shade.size(); ++i) {
        for (std::size_t c = 0; c < 3; ++c) {
            image.rgb[3 * i + c] = static_cast<std::uint8_t>(
                std::lround(static_cast<float>(image.rgb[3 * i + c]) * shade[i]));
        }
    }
}

}  // namespace beamtrace
