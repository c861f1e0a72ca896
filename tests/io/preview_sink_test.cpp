// preview.png: north up, heights in jet over the data's range, cropped to the data, a white
// scale bar at the bottom left, and a note with its scale.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/io/png_reader.hpp"
#include "beamtrace/io/point_sink_registry.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// A 10 m x 10 m ground at z 0 sampled every 5 cm, with a 5 m block over its north-east quarter.
PointBlock ground_with_block() {
    PointBlock block;
    for (int i = 0; i < 200; ++i) {
        for (int j = 0; j < 200; ++j) {
            BlockPoint& p = block.points.emplace_back();
            p.x = 0.025 + 0.05 * i;
            p.y = 0.025 + 0.05 * j;
            p.z = (p.x > 5 && p.y > 5) ? 5.0 : 0.0;
        }
    }
    return block;
}

TEST(PreviewSink, NorthUpHeightsInColourCroppedWithAScaleBar) {
    test::TempDir dir;
    SinkFacts facts;
    facts.output_dir = dir.path();
    facts.lo_m = {-100, -100, 0};
    facts.hi_m = {100, 100, 10};
    facts.footprint_m = {{-1, -1, 0}, {11, 11, 5}};
    facts.pulses = 40000;
    auto sink = point_sink("preview").make(facts);
    const PointBlock block = ground_with_block();
    auto buffer = sink->make_buffer();
    sink->encode(block, *buffer);
    sink->write(*buffer);
    const auto files = sink->commit();
    ASSERT_EQ(files.size(), 1u);
    ASSERT_EQ(sink->notes().size(), 1u);
    const std::string note = sink->notes()[0];
    EXPECT_NE(note.find("pixels of 0.09 m, north up, heights 0.00 to 5.00 m"), std::string::npos)
        << note;

    const RgbImage img = read_png_rgb8(files[0]);
    // 1.5 point spacings (0.09 m) per pixel: 10 m of data is 111 pixels, plus 8 of margin on
    // each side (the footprint reaches 1 m beyond the data).
    EXPECT_EQ(img.width, 111 + 16);
    EXPECT_EQ(img.height, 111 + 16);
    const auto px = [&](int x, int y) {
        const auto i = 3 * (static_cast<std::size_t>(y) * img.width + x);
        return std::array<int, 3>{img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]};
    };
    const auto ne = px(img.width * 3 / 4, img.height / 4);  // north-east: high, red
    const auto sw = px(img.width / 3, img.height * 2 / 3);  // south-west: low, blue
    EXPECT_GT(ne[0], 100);
    EXPECT_LT(ne[2], 20);
    EXPECT_GT(sw[2], 100);
    EXPECT_LT(sw[0], 20);
    EXPECT_EQ(px(2, 2), (std::array<int, 3>{40, 40, 40}));  // the margin: no data
    // The scale bar (1 m: a quarter of the width, 1-2-5 below) is white at the bottom left.
    EXPECT_NE(note.find("scale bar 2 m"), std::string::npos) << note;
    EXPECT_EQ(px(10, img.height - 8), (std::array<int, 3>{255, 255, 255}));
}

/// preview.png of `blocks` (points of one footprint), each encoded on its own thread when
/// `threads`, else in the order given; the file's bytes.
std::string preview_of(const std::vector<PointBlock>& blocks, bool threads) {
    test::TempDir dir;
    SinkFacts facts;
    facts.output_dir = dir.path();
    facts.lo_m = {-1, -1, -1};
    facts.hi_m = {11, 11, 6};
    facts.pulses = 40000;
    auto sink = point_sink("preview").make(facts);
    std::vector<std::unique_ptr<SinkBuffer>> buffers;
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        buffers.push_back(sink->make_buffer());
    }
    if (threads) {
        std::vector<std::thread> pool;
        for (std::size_t k = 0; k < blocks.size(); ++k) {
            pool.emplace_back([&, k] { sink->encode(blocks[k], *buffers[k]); });
        }
        for (auto& t : pool) {
            t.join();
        }
    } else {
        for (std::size_t k = 0; k < blocks.size(); ++k) {
            sink->encode(blocks[k], *buffers[k]);
        }
    }
    for (const auto& b : buffers) {
        sink->write(*b);
    }
    const auto files = sink->commit();
    return files.empty() ? std::string() : test::read_file(files[0]);
}

TEST(PreviewSink, TheSameImageForBlocksEncodedInAnyOrderOnAnyThreads) {
    // The ground and block, each pixel hit many times at heights shuffled across 8 blocks
    // (and a -0 beside +0): the highest of each pixel wins whoever encodes it.
    PointBlock all = ground_with_block();
    std::mt19937 rng(7);
    for (BlockPoint& p : all.points) {
        p.z += std::uniform_real_distribution<double>(-0.5, 0.5)(rng);
    }
    all.points[0].z = -0.0;
    all.points[1].z = 0.0;
    std::shuffle(all.points.begin(), all.points.end(), rng);
    std::vector<PointBlock> blocks(8);
    for (std::size_t i = 0; i < all.points.size(); ++i) {
        blocks[i % blocks.size()].points.push_back(all.points[i]);
    }
    const std::string one = preview_of({all}, false);
    ASSERT_FALSE(one.empty());
    EXPECT_EQ(preview_of(blocks, false), one);
    std::reverse(blocks.begin(), blocks.end());
    EXPECT_EQ(preview_of(blocks, false), one);
    for (int round = 0; round < 4; ++round) {
        EXPECT_EQ(preview_of(blocks, true), one) << "round " << round;
    }
}

TEST(PreviewSink, GapsOfUpToTwoPixelsClosedAlongRowsAndColumnsAtTheLowerHeight) {
    // Pixels of 100 m / 1024 (the footprint's side over kPreviewPixels); a point at the centre
    // of pixel (u, v), v counted from the north edge.
    test::TempDir dir;
    SinkFacts facts;
    facts.output_dir = dir.path();
    facts.footprint_m = {{0, 0, 0}, {100, 100, 10}};
    facts.pulses = 100000000;
    auto sink = point_sink("preview").make(facts);
    const double cell = 100.0 / 1024;
    PointBlock block;
    const auto hit = [&](int u, int v, double z) {
        BlockPoint& p = block.points.emplace_back();
        p.x = (u + 0.5) * cell;
        p.y = 100.0 - (v + 0.5) * cell;
        p.z = z;
    };
    // Along row 20: gaps of 1, 2 and 3 pixels; down column 30 the same.
    for (const int k : {10, 12, 15, 19, 20}) {
        hit(k, 20, k == 12 ? 3.0 : 1.0);
        hit(30, k + 10, 2.0);
    }
    auto buffer = sink->make_buffer();
    sink->encode(block, *buffer);
    sink->write(*buffer);
    const auto files = sink->commit();
    ASSERT_EQ(files.size(), 1u);
    // Cropped to columns 10-30 and rows 20-30 with 8 pixels of margin.
    EXPECT_NE(sink->notes()[0].find("37 x 27 pixels of 0.0977 m, north up, heights 1.00 to 3.00"),
              std::string::npos)
        << sink->notes()[0];
    const RgbImage img = read_png_rgb8(files[0]);
    ASSERT_EQ(img.width, 37);
    ASSERT_EQ(img.height, 27);
    const auto filled = [&](int u, int v) {
        const auto i = 3 * (static_cast<std::size_t>(v - 12) * img.width + (u - 2));
        return img.rgb[i] != 40 || img.rgb[i + 1] != 40 || img.rgb[i + 2] != 40;
    };
    for (int k = 9; k <= 21; ++k) {
        const bool want = (k >= 10 && k <= 15) || (k >= 19 && k <= 20);
        EXPECT_EQ(filled(k, 20), want) << "row 20, column " << k;
        EXPECT_EQ(filled(30, k + 10), want) << "column 30, row " << k + 10;
    }
    // The gaps beside pixel 12 (3 m: red) at the lower height (1 m: blue, no red).
    const auto red_blue = [&](int u, int v) {
        const auto i = 3 * (static_cast<std::size_t>(v - 12) * img.width + (u - 2));
        return std::pair<int, int>{img.rgb[i], img.rgb[i + 2]};
    };
    EXPECT_GT(red_blue(12, 20).first, 0);
    EXPECT_EQ(red_blue(12, 20).second, 0);
    for (const int u : {11, 13}) {
        EXPECT_EQ(red_blue(u, 20).first, 0) << u;
        EXPECT_GT(red_blue(u, 20).second, 0) << u;
    }
}

TEST(PreviewSink, NoPointsNoFile) {
    test::TempDir dir;
    SinkFacts facts;
    facts.output_dir = dir.path();
    facts.lo_m = {0, 0, 0};
    facts.hi_m = {1, 1, 1};
    auto sink = point_sink("preview").make(facts);
    EXPECT_TRUE(sink->commit().empty());
    EXPECT_FALSE(std::filesystem::exists(dir / "preview.png"));
}

}  // namespace
}  // namespace beamtrace
