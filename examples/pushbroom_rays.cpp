// Writes the rays of the report's push-broom example (section 3.4.3, Appendix B.1) as a rays
// file for `beamtrace scan --pattern rays`: a 1-pixel-wide pinhole line scanner flown from
// (-50,-50) to (50,50) at a fixed height with yaw pi/4, pitching -pi/2 + sin(4 pi t) degrees, one
// line of H pixels per step, H steps, all aggregated into one ray list in the report's order.
//
//   beamtrace_pushbroom_rays OUT.csv [H=500] [HEIGHT_M=200]
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "beamtrace/sensor/rays_file.hpp"

int main(int argc, char** argv) {
    namespace bt = beamtrace;
    if (argc < 2 || argc > 4) {
        std::fprintf(stderr, "usage: %s OUT.csv [H=500] [HEIGHT_M=200]\n", argv[0]);
        return 2;
    }
    try {
        const int h = argc > 2 ? std::stoi(argv[2]) : 500;
        const double z = argc > 3 ? std::stod(argv[3]) : 200.0;
        if (h < 2) {
            throw bt::ConfigError("H must be at least 2");
        }
        const double pi = std::numbers::pi;
        bt::RayBatch all;
        all.reserve(static_cast<std::size_t>(h) * static_cast<std::size_t>(h));
        for (int i = 0; i < h; ++i) {
            const double t = static_cast<double>(i) / (h - 1);  // linspace(0, 1, h)
            bt::ImageSensorConfig line;
            line.position_m = {-50.0 + 100.0 * t, -50.0 + 100.0 * t, z};
            line.orientation = {0.0, -pi / 2 + (pi / 180) * std::sin(t * 4 * pi), pi / 4};
            line.width = 1;
            line.height = h;
            line.hfov_rad = (pi / 9) / h;
            line.vfov_rad = pi / 9;
            const bt::RayBatch rays = bt::cast_rays_pinhole(line);
            for (std::size_t k = 0; k < rays.size(); ++k) {
                all.push_back(rays.origin(k), rays.direction(k));
            }
        }
        bt::write_rays_csv(argv[1], all);
        std::printf("wrote %zu rays (%d lines of %d) to %s\n", all.size(), h, h, argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    return 0;
}
