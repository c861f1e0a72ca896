// Eye-dome lighting: darkens exactly the pixels behind nearer neighbours, by the documented
// factor, and the same at any thread count.
#include "beamtrace/heightfield/eye_dome.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "beamtrace/core/thread_pool.hpp"

namespace beamtrace {
namespace {

/// A 16 x 8 image, grey 200: depth 10 on the left half, 20 on the right, a miss at (3, 3).
ViewImage step_image() {
    ViewImage image;
    image.width = 16;
    image.height = 8;
    image.rgb.assign(16 * 8 * 3, 200);
    image.depth.resize(16 * 8);
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 16; ++x) {
            image.depth[static_cast<std::size_t>(y * 16 + x)] = x < 8 ? 10.0f : 20.0f;
        }
    }
    image.depth[3 * 16 + 3] = std::numeric_limits<float>::infinity();
    return image;
}

TEST(EyeDome, OnlyPixelsBehindANearerNeighbourDarken) {
    const ViewImage image = step_image();
    ThreadPool pool(1);
    ViewImage shaded = image;
    apply_eye_dome(shaded, 1.0, pool);
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 16; ++x) {
            const std::size_t i = static_cast<std::size_t>(y * 16 + x);
            // Far pixels within 2 columns of the step see 3 nearer neighbours (2 at the image's
            // top and bottom rows): log2(20 / 10) = 1 each.
            double expected = 200.0;
            if (x == 8 || x == 9) {
                const int nearer = (y >= 2 && y <= 5) ? 3 : 2;
                expected = 200.0 * std::exp(-100.0 * nearer / 8.0);
            }
            EXPECT_EQ(shaded.rgb[3 * i], static_cast<std::uint8_t>(std::lround(expected)))
                << x << "," << y;
        }
    }
    // The miss, and its neighbours (a miss counts as far), keep their colour.
    EXPECT_EQ(shaded.rgb[3 * (3 * 16 + 3)], 200);
    EXPECT_EQ(shaded.rgb[3 * (3 * 16 + 5)], 200);
    // The documented factor, at a pixel with one nearer neighbour of 1.5x less depth.
    ViewImage one = image;
    for (auto& d : one.depth) {
        d = 15.0f;
    }
    one.depth[4 * 16 + 12] = 10.0f;
    EXPECT_NEAR(eye_dome_shade(one, 10, 4, 0.5), std::exp(-50.0 * std::log2(1.5) / 8.0), 1e-12);
    EXPECT_EQ(eye_dome_shade(one, 11, 4, 0.5), 1.0);  // not at the radius
}

TEST(EyeDome, StrengthZeroChangesNothingAndThreadsDoNot) {
    ViewImage image = step_image();
    for (std::size_t i = 0; i < image.depth.size(); ++i) {
        image.depth[i] *= 1.0f + 0.01f * static_cast<float>(i % 7);  // ragged depths
    }
    ThreadPool one(1), three(3);
    ViewImage off = image;
    apply_eye_dome(off, 0.0, one);
    EXPECT_EQ(off.rgb, image.rgb);
    ViewImage a = image, b = image;
    apply_eye_dome(a, 0.7, one);
    apply_eye_dome(b, 0.7, three);
    EXPECT_EQ(a.rgb, b.rgb);
    EXPECT_NE(a.rgb, image.rgb);
}

}  // namespace
}  // namespace beamtrace
