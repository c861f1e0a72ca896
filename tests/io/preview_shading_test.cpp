// preview.png's pixel colours: the rounding (round_to_int32, shared with the LAS writer), the
// scalar row against the formula written out here with the library's own pieces (jet_color,
// normalize, std::lround), and the AVX2 lanes against the scalar row, byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/io/colormap.hpp"
#include "io/detail/round_int32.hpp"
#include "io/sinks/preview_shading.hpp"

namespace beamtrace::detail {
namespace {

constexpr float kEmpty = -std::numeric_limits<float>::infinity();

TEST(PreviewShading, RoundToInt32IsLround) {
    std::vector<double> values = {
        0.0,   0.49999999999999994, 0.5, 0.5000000000000001, 1.0, 1.5, 2.5, 254.5,
        255.0, 2147483647.0};
    for (double v : {0.5, 1.5, 2.5, 127.5, 254.5, 1e9 + 0.5}) {
        values.push_back(std::nextafter(v, 0.0));
        values.push_back(std::nextafter(v, 1e10));
    }
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 300.0);
    for (int i = 0; i < 100000; ++i) {
        values.push_back(u(rng));
    }
    for (const double v : values) {
        ASSERT_EQ(round_to_int32(v), std::lround(v)) << v;
        ASSERT_EQ(round_to_int32(-v), std::lround(-v)) << -v;
    }
}

/// The preview's pixel as the formula reads: jet of the height's place, each channel rounded,
/// darkened by the hill shade of the neighbours (clamped at the edges, empty ones as the pixel's
/// own height) under a light from the north-west 45 degrees up, rounded again.
std::array<std::uint8_t, 3> formula_pixel(const PreviewRows& r, const PreviewShading& s, int x) {
    const auto z = [&](const float* line, int u) {
        const float h = line[std::clamp(u, 0, r.width - 1)];
        return static_cast<double>(h == kEmpty ? r.row[x] : h);
    };
    const double gx = (z(r.row, x + 1) - z(r.row, x - 1)) / (2.0 * s.cell_m);
    const double gy = (z(r.up, x) - z(r.down, x)) / (2.0 * s.cell_m);
    const Vec3d n = normalize(Vec3d{-gx, -gy, 1.0});
    const Vec3d light = normalize(Vec3d{-1.0, 1.0, std::sqrt(2.0)});
    const double shade = std::clamp(0.35 + 0.65 * std::max(0.0, dot(n, light)) / light.z, 0.0, 1.0);
    const double t = s.span > 0 ? (static_cast<double>(r.row[x]) - s.z_lo) / s.span : 0.5;
    auto colour = jet_color(t);
    for (auto& ch : colour) {
        ch = static_cast<std::uint8_t>(std::lround(ch * shade));
    }
    return colour;
}

/// Three rows of `width` heights: steep and flat stretches, empty pixels (a share `empty_share`),
/// some heights beyond the span's ends (clamped colours).
std::vector<float> random_rows(int width, double empty_share, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> z(3 * static_cast<std::size_t>(width));
    float h = 50.0f;
    for (float& v : z) {
        const float step = u(rng) < 0.2f ? 40.0f * (u(rng) - 0.5f) : 0.3f * (u(rng) - 0.5f);
        h = std::clamp(h + step, -20.0f, 140.0f);
        v = u(rng) < empty_share ? kEmpty : h;
    }
    return z;
}

TEST(PreviewShading, ScalarRowIsTheFormula) {
    std::mt19937 rng(11);
    for (const int width : {1, 2, 3, 7, 64}) {
        for (const double empty : {0.0, 0.3}) {
            const auto z = random_rows(width, empty, rng);
            const PreviewRows rows{z.data(), z.data() + width, z.data() + 2 * width, width, kEmpty};
            for (const PreviewShading s :
                 {PreviewShading{10.0, 100.0, 0.7}, PreviewShading{30.0, 0.0, 2.0}}) {
                std::vector<std::uint8_t> rgb(3 * static_cast<std::size_t>(width), 40);
                shade_preview_row_scalar(rows, s, 0, width, rgb.data());
                for (int x = 0; x < width; ++x) {
                    const std::array<std::uint8_t, 3> want =
                        rows.row[x] == kEmpty ? std::array<std::uint8_t, 3>{40, 40, 40}
                                              : formula_pixel(rows, s, x);
                    for (int k = 0; k < 3; ++k) {
                        ASSERT_EQ(rgb[3 * x + k], want[k]) << "width " << width << " x " << x;
                    }
                }
            }
        }
    }
}

TEST(PreviewShading, RowInLanesIsTheScalarRowByteForByte) {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 400; ++trial) {
        const int width = 1 + static_cast<int>(rng() % 70);
        const auto z = random_rows(width, (trial % 4) * 0.2, rng);
        const PreviewRows rows{z.data(), z.data() + width, z.data() + 2 * width, width, kEmpty};
        const int x0 = static_cast<int>(rng() % static_cast<unsigned>(width));
        const int x1 = x0 + 1 + static_cast<int>(rng() % static_cast<unsigned>(width - x0));
        const PreviewShading s{trial % 3 == 0 ? 0.0 : 10.0, trial % 5 == 0 ? 0.0 : 90.0,
                               0.25 + (trial % 7)};
        std::vector<std::uint8_t> lanes(3 * static_cast<std::size_t>(x1 - x0), 40);
        auto scalar = lanes;
        shade_preview_row(rows, s, x0, x1, lanes.data());
        shade_preview_row_scalar(rows, s, x0, x1, scalar.data());
        ASSERT_EQ(lanes, scalar) << "trial " << trial << " width " << width << " [" << x0 << ", "
                                 << x1 << ")";
    }
}

}  // namespace
}  // namespace beamtrace::detail
